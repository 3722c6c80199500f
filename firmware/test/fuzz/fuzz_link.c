/* Fuzz target for the device's frame parser and dispatcher.
 * libFuzzer entry point LLVMFuzzerTestOneInput (clang -fsanitize=fuzzer); with -DSL_FUZZ_STANDALONE a
 * small driver mutates the seed files with a fixed-seed PRNG for a bounded time (gcc builds).
 * Invariants checked on every input, beyond the sanitizers' memory and UB checks:
 *   - every output pulse is 0 or inside the channel's configured [min_us, max_us];
 *   - no pulses unless the link is ARMED / HOLD / PARK;
 *   - every byte the device sends decodes as a valid frame;
 *   - a NAK for an undecodable frame carries seq 0xFF;
 *   - the outputs change only when a frame was accepted with an ACK or the clock ticked. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "link.h"

typedef struct {
    sl_rx_t rx;
    int replies, acks;
} sink_t;

static void fz_abort(const char *why)
{
    fprintf(stderr, "fuzz invariant violated: %s\n", why);
    abort();
}

static void sink_tx(void *user, const uint8_t *buf, uint8_t len)
{
    sink_t *s = (sink_t *)user;
    if (len < 5 || buf[len - 1] != 0)
        fz_abort("reply frame shape");
    for (uint8_t i = 0; i < len; i++) {
        sl_packet_t p;
        uint8_t err = 0;
        uint8_t r = sl_rx_feed(&s->rx, buf[i], &p, &err);
        if (r == SL_RX_ERR)
            fz_abort("device sent an undecodable frame");
        if (r == SL_RX_OK) {
            s->replies++;
            if (p.type == SL_T_ACK)
                s->acks++;
            if (p.type == SL_T_NAK && p.payload[0] <= SL_E_TOO_LONG && p.seq != SL_SEQ_NONE)
                fz_abort("framing NAK without seq 0xFF");
        }
    }
}

static void check_outputs(const sl_link_t *l)
{
    int on = l->state == SL_ST_ARMED || l->state == SL_ST_HOLD || l->state == SL_ST_PARK;
    for (uint8_t ch = 0; ch < l->n_ch; ch++) {
        uint16_t us = l->out_us[ch];
        if (!on && us)
            fz_abort("pulses while disarmed/released");
        if (us && (us < l->cfg[ch].min_us || us > l->cfg[ch].max_us))
            fz_abort("pulse outside the channel range");
        if (sl_chan_cfg_check(&l->cfg[ch]))
            fz_abort("invalid channel config accepted");
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static sl_link_t l;
    sink_t s;
    memset(&s, 0, sizeof s);
    sl_rx_init(&s.rx);
    uint32_t now = 0;
    sl_link_init(&l, SL_MAX_CH, 0, sink_tx, NULL, &s, now);
    /* The input is a byte stream for the link with two escapes:
     *   0xFE k            advance the clock by k * 8 ms (watchdog, slew, generators);
     *   0xFD n t p[n-1]   a *valid* frame of type t with payload p, built here with its COBS and CRC, so that
     *                     the fuzzer reaches the dispatcher without having to forge CRCs.
     * Every other byte goes to the link as it is (framing, COBS and CRC errors). */
    uint8_t seq = 1;
    for (size_t i = 0; i < size; i++) {
        if (data[i] == 0xFE && i + 1 < size) {
            now += (uint32_t)data[++i] * 8u;
            sl_link_tick(&l, now);
            check_outputs(&l);
            continue;
        }
        uint8_t frame[SL_MAX_ENCODED + 1];
        const uint8_t *bytes = &data[i];
        uint8_t nbytes = 1;
        if (data[i] == 0xFD && i + 2 < size) {
            uint8_t n = data[i + 1];
            if (n < 1)
                n = 1;
            if (n > SL_MAX_PAYLOAD + 1)
                n = SL_MAX_PAYLOAD + 1;
            if (i + 2 + n > size)
                n = (uint8_t)(size - i - 2);
            nbytes = sl_build_frame(data[i + 2], seq, &data[i + 3], (uint8_t)(n - 1), frame);
            seq = (uint8_t)(seq >= 254 ? 1 : seq + 1);
            bytes = frame;
            i += 1 + n;
        }
        for (uint8_t k = 0; k < nbytes; k++) {
            uint16_t before[SL_MAX_CH];
            memcpy(before, l.out_us, sizeof before);
            int acks = s.acks;
            sl_link_feed(&l, bytes[k], now);
            if (s.acks == acks && memcmp(before, l.out_us, sizeof before))
                fz_abort("outputs changed without an ACK");
            check_outputs(&l);
        }
    }
    return 0;
}

#ifdef SL_FUZZ_STANDALONE
#include <dirent.h>
#include <time.h>

static uint32_t rng = 0x12345678u;
static uint32_t xr(void)
{
    rng ^= rng << 13;
    rng ^= rng >> 17;
    rng ^= rng << 5;
    return rng;
}

int main(int argc, char **argv)
{
    double seconds = 10;
    const char *dir = NULL;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--seconds") && i + 1 < argc)
            seconds = atof(argv[++i]);
        else
            dir = argv[i];
    }
    static uint8_t seeds[64][512];
    size_t seed_len[64];
    int nseeds = 0;
    if (dir) {
        DIR *d = opendir(dir);
        struct dirent *e;
        while (d && (e = readdir(d)) && nseeds < 64) {
            if (e->d_name[0] == '.')
                continue;
            char path[1024];
            snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
            FILE *f = fopen(path, "rb");
            if (!f)
                continue;
            seed_len[nseeds] = fread(seeds[nseeds], 1, sizeof seeds[0], f);
            fclose(f);
            nseeds++;
        }
        if (d)
            closedir(d);
    }
    if (!nseeds) {
        seed_len[0] = 1;
        seeds[0][0] = 0;
        nseeds = 1;
    }
    clock_t end = clock() + (clock_t)(seconds * CLOCKS_PER_SEC);
    unsigned long runs = 0;
    uint8_t buf[1024];
    while (clock() < end) {
        for (int k = 0; k < 256; k++, runs++) {
            /* splice one or two seeds, then mutate a few bytes */
            size_t n = 0;
            int parts = 1 + (int)(xr() % 3);
            for (int pidx = 0; pidx < parts; pidx++) {
                int sidx = (int)(xr() % (uint32_t)nseeds);
                size_t m = seed_len[sidx];
                if (n + m > sizeof buf)
                    break;
                memcpy(buf + n, seeds[sidx], m);
                n += m;
            }
            int muts = (int)(xr() % 8);
            for (int mu = 0; mu < muts && n; mu++) {
                size_t pos = xr() % n;
                switch (xr() % 4) {
                case 0: buf[pos] ^= (uint8_t)(1u << (xr() % 8)); break;
                case 1: buf[pos] = (uint8_t)xr(); break;
                case 2: buf[pos] = 0; break;
                default: if (n < sizeof buf) buf[n++] = (uint8_t)xr(); break;
                }
            }
            LLVMFuzzerTestOneInput(buf, n);
        }
    }
    printf("fuzz_link: %lu runs in %.0f s, no invariant violated\n", runs, seconds);
    return 0;
}
#endif
