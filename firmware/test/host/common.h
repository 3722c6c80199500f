/* Helpers shared by the host tests: a fake link with captured replies and a fake clock. */
#ifndef TEST_COMMON_H
#define TEST_COMMON_H
#include <string.h>

#include "check.h"
#include "link.h"
#include "minijson.h"

typedef struct {
    sl_packet_t pkt[64];
    int n;
    sl_rx_t rx;
} capture_t;

static inline void cap_tx(void *user, const uint8_t *buf, uint8_t len)
{
    capture_t *c = (capture_t *)user;
    for (uint8_t i = 0; i < len; i++) {
        uint8_t err = 0;
        sl_packet_t p;
        if (sl_rx_feed(&c->rx, buf[i], &p, &err) == SL_RX_OK && c->n < 64)
            c->pkt[c->n++] = p;
    }
}

static inline void fake_link(sl_link_t *l, capture_t *c, uint32_t now)
{
    memset(c, 0, sizeof *c);
    sl_rx_init(&c->rx);
    sl_link_init(l, 8, 0, cap_tx, NULL, c, now);
}

/* send one request, return the last reply packet (or NULL) */
static inline sl_packet_t *request(sl_link_t *l, capture_t *c, uint8_t type, uint8_t seq, const uint8_t *payload, uint8_t n,
                            uint32_t now)
{
    uint8_t frame[SL_MAX_ENCODED + 1];
    uint8_t len = sl_build_frame(type, seq, payload, n, frame);
    int before = c->n;
    for (uint8_t i = 0; i < len; i++)
        sl_link_feed(l, frame[i], now);
    return c->n > before ? &c->pkt[c->n - 1] : NULL;
}

static inline int vec_bytes(const jnode_t *o, const char *key, uint8_t *out, int cap)
{
    const char *h = json_str(o, key);
    return h ? hex_decode(h, out, cap) : -1;
}
#endif
