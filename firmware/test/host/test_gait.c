/* Gait rule (seed 001, Algorithm 1) against the shared vectors, both as a pure function and through
 * the link (GAIT_SET + GAIT_CONTACTS), and GAIT mode driving the servos. */
#include "common.h"

static int load_vec(const jnode_t *v, uint8_t *c, uint8_t *act)
{
    int n = 0;
    jnode_t *a = json_get(v, "c_air")->child, *b = json_get(v, "act")->child;
    for (; a && b; a = a->next, b = b->next, n++) {
        c[n] = (uint8_t)a->num;
        act[n] = (uint8_t)b->num;
    }
    return n;
}

static void test_pure(const jnode_t *root)
{
    int count = 0;
    for (jnode_t *v = json_get(root, "vectors")->child; v; v = v->next, count++) {
        uint8_t c[64], want[64], air[8] = {0}, got[8];
        int n = load_vec(v, c, want);
        for (int i = 0; i < n; i++)
            air[i >> 3] |= (uint8_t)(c[i] << (i & 7));
        sl_gait_step(air, (uint8_t)n, (uint8_t)json_int(v, "n1", 0), (uint8_t)json_int(v, "n2", 0),
                     (uint8_t)json_int(v, "closed", 1), got);
        int bad = 0;
        for (int i = 0; i < n; i++)
            bad += ((got[i >> 3] >> (i & 7)) & 1) != want[i];
        CHECK(bad == 0, "%s: %d cells differ", json_str(v, "name"), bad);
    }
    CHECK(count >= 10, "gait vectors %d", count);
}

static void test_link(const jnode_t *root)
{
    for (jnode_t *v = json_get(root, "vectors")->child; v; v = v->next) {
        uint8_t c[64], want[64];
        int n = load_vec(v, c, want);
        sl_link_t l;
        capture_t cap;
        fake_link(&l, &cap, 0);
        uint8_t gs[9] = {(uint8_t)n, (uint8_t)json_int(v, "n1", 0), (uint8_t)json_int(v, "n2", 0),
                         (uint8_t)(json_int(v, "closed", 1) ? SL_GAIT_CLOSED : 0), 0};
        sl_put_u16(gs + 5, 4500);
        sl_put_u16(gs + 7, 0);
        sl_packet_t *r = request(&l, &cap, SL_T_GAIT_SET, 1, gs, 9, 0);
        CHECK(r && r->type == SL_T_ACK, "%s: GAIT_SET", json_str(v, "name"));
        uint8_t air[8] = {0};
        for (int i = 0; i < n; i++)
            air[i >> 3] |= (uint8_t)(c[i] << (i & 7));
        r = request(&l, &cap, SL_T_GAIT_CONTACTS, 2, air, (uint8_t)((n + 7) / 8), 1);
        CHECK(r && r->type == SL_T_ACK && r->plen == 2 + (n + 7) / 8, "%s: GAIT_CONTACTS", json_str(v, "name"));
        if (!r || r->type != SL_T_ACK)
            continue;
        int bad = 0;
        for (int i = 0; i < n; i++)
            bad += ((r->payload[2 + (i >> 3)] >> (i & 7)) & 1) != want[i];
        CHECK(bad == 0, "%s via link: %d cells differ", json_str(v, "name"), bad);
    }
}

static void test_mode(void)
{
    /* 8-cell belt, high torque n1 = n2 = 1; cells 0..2 on the ground -> cells 3 and 7 inflate */
    sl_link_t l;
    capture_t cap;
    fake_link(&l, &cap, 0);
    uint8_t gs[9] = {8, 1, 1, SL_GAIT_CLOSED, 0};
    sl_put_u16(gs + 5, 6000);
    sl_put_u16(gs + 7, (uint16_t)-3000);
    request(&l, &cap, SL_T_GAIT_SET, 1, gs, 9, 0);
    uint8_t air = 0xF8;
    request(&l, &cap, SL_T_GAIT_CONTACTS, 2, &air, 1, 0);
    request(&l, &cap, SL_T_ARM, 3, NULL, 0, 0);
    uint8_t m = SL_MODE_GAIT;
    sl_packet_t *r = request(&l, &cap, SL_T_SET_MODE, 4, &m, 1, 0);
    CHECK(r && r->type == SL_T_ACK, "SET_MODE GAIT");
    for (uint32_t t = 1; t < 50; t++)
        sl_link_tick(&l, t);
    uint16_t inflate = 1500 + 667, vent = 1500 - 333; /* 60 deg -> 2166.7, -30 deg -> 1166.7 */
    for (int ch = 0; ch < 8; ch++) {
        uint16_t want = (ch == 3 || ch == 7) ? inflate : vent;
        CHECK(l.out_us[ch] == want, "gait ch%d: %u us, want %u", ch, l.out_us[ch], want);
    }
    /* out-of-range parameters are refused */
    uint8_t bad[9] = {8, 8, 0, SL_GAIT_CLOSED, 0};
    r = request(&l, &cap, SL_T_GAIT_SET, 5, bad, 9, 60);
    CHECK(r && r->type == SL_T_NAK && r->payload[0] == SL_E_RANGE && r->payload[1] == 2, "n1 = n refused");
}

int main(int argc, char **argv)
{
    if (argc < 3) {
        fprintf(stderr, "usage: test_gait protocol.json gait_rule.json\n");
        return 2;
    }
    jnode_t *root = json_load(argv[2]);
    CHECK(root != NULL, "vectors %s", argv[2]);
    if (root) {
        test_pure(root);
        test_link(root);
    }
    test_mode();
    return check_summary("test_gait");
}
