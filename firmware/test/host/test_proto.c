/* Framing: CRC, COBS, frame build and the receive accumulator, against the shared vectors. */
#include "common.h"

static void test_vectors(const jnode_t *root)
{
    uint8_t a[600], b[600], out[700];
    for (jnode_t *v = json_get(root, "crc16")->child; v; v = v->next) {
        int n = vec_bytes(v, "data_hex", a, sizeof a);
        CHECK(sl_crc16(a, (uint16_t)n) == (uint16_t)json_int(v, "crc", -1), "crc of %s", json_str(v, "data_hex"));
    }
    int ncobs = 0;
    for (jnode_t *v = json_get(root, "cobs")->child; v; v = v->next, ncobs++) {
        int n = vec_bytes(v, "data_hex", a, sizeof a);
        int m = vec_bytes(v, "enc_hex", b, sizeof b);
        uint16_t e = sl_cobs_encode(a, (uint16_t)n, out);
        CHECK(e == m && !memcmp(out, b, (size_t)m), "cobs encode %s: %u vs %d bytes", json_str(v, "name"), e, m);
        int16_t d = sl_cobs_decode(b, (uint16_t)m, out, sizeof out);
        CHECK(d == n && !memcmp(out, a, (size_t)n), "cobs decode %s", json_str(v, "name"));
    }
    CHECK(ncobs >= 11, "cobs vectors: %d", ncobs);
    for (jnode_t *v = json_get(root, "cobs_invalid")->child; v; v = v->next) {
        int m = vec_bytes(v, "enc_hex", b, sizeof b);
        CHECK(sl_cobs_decode(b, (uint16_t)m, out, sizeof out) < 0, "invalid cobs %s accepted", json_str(v, "name"));
    }
    for (jnode_t *v = json_get(root, "frames")->child; v; v = v->next) {
        int n = vec_bytes(v, "payload_hex", a, sizeof a);
        int m = vec_bytes(v, "frame_hex", b, sizeof b);
        uint8_t len = sl_build_frame((uint8_t)json_int(v, "type", 0), (uint8_t)json_int(v, "seq", 0), a, (uint8_t)n, out);
        CHECK(len == m && !memcmp(out, b, (size_t)m), "frame %s", json_str(v, "name"));
        /* and the accumulator decodes it back */
        sl_rx_t rx;
        sl_rx_init(&rx);
        sl_packet_t p;
        uint8_t err = 0, r = 0;
        for (int i = 0; i < m; i++)
            r = sl_rx_feed(&rx, b[i], &p, &err);
        CHECK(r == SL_RX_OK && p.type == json_int(v, "type", 0) && p.seq == json_int(v, "seq", 0) && p.plen == n &&
                  !memcmp(p.payload, a, (size_t)n),
              "rx %s", json_str(v, "name"));
    }
}

/* every single-bit flip of a golden frame is rejected or at worst ends the frame early;
 * it is never accepted as a different packet */
static void test_bitflips(void)
{
    const uint8_t pl[5] = {0x02, 0x28, 0x23, 0xd8, 0xdc};
    uint8_t f[SL_MAX_ENCODED + 1];
    uint8_t len = sl_build_frame(0x10, 42, pl, 5, f);
    int accepted_wrong = 0, rejected = 0;
    for (int i = 0; i < len - 1; i++) {
        for (int bit = 0; bit < 8; bit++) {
            uint8_t g[SL_MAX_ENCODED + 1];
            memcpy(g, f, len);
            g[i] ^= (uint8_t)(1u << bit);
            sl_rx_t rx;
            sl_rx_init(&rx);
            sl_packet_t p;
            uint8_t err = 0;
            for (int k = 0; k < len; k++) {
                uint8_t r = sl_rx_feed(&rx, g[k], &p, &err);
                if (r == SL_RX_OK && !(p.type == 0x10 && p.seq == 42 && p.plen == 5 && !memcmp(p.payload, pl, 5)))
                    accepted_wrong++;
                if (r == SL_RX_ERR)
                    rejected++;
            }
        }
    }
    CHECK(accepted_wrong == 0, "%d corrupted frames accepted", accepted_wrong);
    CHECK(rejected >= 8 * (len - 1) - 8, "only %d of %d flips rejected", rejected, 8 * (len - 1));
}

static void test_resync(void)
{
    sl_rx_t rx;
    sl_rx_init(&rx);
    sl_packet_t p;
    uint8_t err = 0, r;
    /* 100 bytes of junk without a delimiter: too long at the next delimiter */
    for (int i = 0; i < 100; i++)
        CHECK(sl_rx_feed(&rx, 0x55, &p, &err) == SL_RX_NONE, "junk byte %d", i);
    r = sl_rx_feed(&rx, 0, &p, &err);
    CHECK(r == SL_RX_ERR && err == SL_E_TOO_LONG, "oversize: r=%u err=%u", r, err);
    /* a lone delimiter is ignored */
    CHECK(sl_rx_feed(&rx, 0, &p, &err) == SL_RX_NONE, "empty frame");
    /* the next valid frame is received */
    uint8_t f[SL_MAX_ENCODED + 1];
    uint8_t pl[1] = {1};
    uint8_t len = sl_build_frame(SL_T_HELLO, 3, pl, 1, f);
    r = 0;
    for (int i = 0; i < len; i++)
        r = sl_rx_feed(&rx, f[i], &p, &err);
    CHECK(r == SL_RX_OK && p.type == SL_T_HELLO && p.seq == 3, "recover after junk");
    /* maximal payload round trip, and one byte more is refused by the builder */
    uint8_t big[SL_MAX_PAYLOAD + 1];
    for (int i = 0; i <= SL_MAX_PAYLOAD; i++)
        big[i] = (uint8_t)(i * 7);
    len = sl_build_frame(0x20, 9, big, SL_MAX_PAYLOAD, f);
    CHECK(len > 0 && len <= SL_MAX_ENCODED + 1, "max frame length %u", len);
    for (int i = 0; i < len; i++)
        r = sl_rx_feed(&rx, f[i], &p, &err);
    CHECK(r == SL_RX_OK && p.plen == SL_MAX_PAYLOAD && !memcmp(p.payload, big, SL_MAX_PAYLOAD), "max payload");
    CHECK(sl_build_frame(0x20, 9, big, SL_MAX_PAYLOAD + 1, f) == 0, "oversize payload built");
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: test_proto protocol.json\n");
        return 2;
    }
    jnode_t *root = json_load(argv[1]);
    CHECK(root != NULL, "vectors %s", argv[1]);
    if (root)
        test_vectors(root);
    test_bitflips();
    test_resync();
    return check_summary("test_proto");
}
