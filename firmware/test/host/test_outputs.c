/* Output invariants of the link (issue 19): every pulse is computed from (state, mode, limits, trim, override)
 * whenever any of them changes, so no stale value survives, and the limits hold in every mode. One test per
 * defect found by the invariant fuzzer, each written against today's code first. Expected widths in closed
 * form from PROTOCOL.md section 5: us = (min + max) / 2 + a (max - min) / 180 deg, rounded half up. */
#include <stdlib.h>

#include "common.h"

static sl_packet_t *cfg_ch(sl_link_t *l, capture_t *c, uint8_t ch, uint16_t min_us, uint16_t max_us, int16_t trim,
                           uint8_t invert, int16_t lo, int16_t hi, int16_t park, uint16_t slew, uint8_t seq, uint32_t now)
{
    uint8_t p[16] = {ch};
    sl_put_u16(p + 1, min_us);
    sl_put_u16(p + 3, max_us);
    sl_put_u16(p + 5, (uint16_t)trim);
    p[7] = invert;
    sl_put_u16(p + 8, (uint16_t)lo);
    sl_put_u16(p + 10, (uint16_t)hi);
    sl_put_u16(p + 12, (uint16_t)park);
    sl_put_u16(p + 14, slew);
    return request(l, c, SL_T_CONFIG_CH, seq, p, 16, now);
}

static int acked(const sl_packet_t *r)
{
    return r && r->type == SL_T_ACK;
}

/* defect 1: DISARM, CONFIG_CH 1600..2600 us, ARM gave 1500 us (outside the new range); a trim change made while
 * the pulses were off was ignored too */
static void test_config_while_disarmed(void)
{
    sl_link_t l;
    capture_t c;
    fake_link(&l, &c, 0);
    CHECK(acked(request(&l, &c, SL_T_ARM, 1, NULL, 0, 0)), "ARM");
    CHECK(l.out_us[0] == 1500, "armed at 0 deg: %u", l.out_us[0]);
    CHECK(acked(request(&l, &c, SL_T_DISARM, 2, NULL, 0, 1)), "DISARM");
    CHECK(acked(cfg_ch(&l, &c, 0, 1600, 2600, 0, 0, -9000, 9000, 0, 0, 3, 2)), "CONFIG_CH 1600..2600");
    CHECK(acked(cfg_ch(&l, &c, 1, 500, 2500, 500, 0, -9000, 9000, 0, 0, 4, 3)), "CONFIG_CH trim 5 deg");
    CHECK(acked(request(&l, &c, SL_T_ARM, 5, NULL, 0, 4)), "ARM again");
    CHECK(l.out_us[0] == 2100, "new range: 0 deg is (1600 + 2600) / 2 = 2100 us, got %u", l.out_us[0]);
    CHECK(l.out_us[1] == 1556, "trim 5 deg: 1500 + 5 * 2000 / 180 = 1555.6 -> 1556 us, got %u", l.out_us[1]);
    /* the same after a tick (the main loop's path) */
    sl_link_tick(&l, 20);
    CHECK(l.out_us[0] == 2100 && l.out_us[1] == 1556, "after a tick: %u %u", l.out_us[0], l.out_us[1]);
}

/* defect 2: a SET_PULSES override survived a narrowing CONFIG_CH (2500 us with max_us 2000) */
static void test_override_narrowed(void)
{
    sl_link_t l;
    capture_t c;
    fake_link(&l, &c, 0);
    request(&l, &c, SL_T_ARM, 1, NULL, 0, 0);
    uint8_t p[4] = {0, 1};
    sl_put_u16(p + 2, 2500);
    CHECK(acked(request(&l, &c, SL_T_SET_PULSES, 2, p, 4, 1)), "SET_PULSES 2500");
    CHECK(l.out_us[0] == 2500, "override %u", l.out_us[0]);
    CHECK(acked(cfg_ch(&l, &c, 0, 1000, 2000, 0, 0, -9000, 9000, 0, 0, 3, 2)), "CONFIG_CH max 2000");
    CHECK(l.out_us[0] >= 1000 && l.out_us[0] <= 2000, "override inside the new range: %u", l.out_us[0]);
    CHECK(l.out_us[0] == 2000, "override clamped to max_us: %u", l.out_us[0]);
    /* soft limits narrowed to [-45, 45] deg: the pulse window is [1250, 1750] us */
    CHECK(acked(cfg_ch(&l, &c, 0, 1000, 2000, 0, 0, -4500, 4500, 0, 0, 4, 3)), "CONFIG_CH +-45 deg");
    CHECK(l.out_us[0] == 1750, "override clamped to the soft limit's pulse: %u", l.out_us[0]);
    sl_link_tick(&l, 30);
    CHECK(l.out_us[0] == 1750, "after a tick: %u", l.out_us[0]);
}

/* defect 3: GAIT mode ignored soft limits changed after GAIT_SET (driven to -80 deg with limits +-10 deg) */
static void test_gait_obeys_later_limits(void)
{
    sl_link_t l;
    capture_t c;
    fake_link(&l, &c, 0);
    uint8_t g[9] = {8, 1, 1, SL_GAIT_CLOSED, 0};
    sl_put_u16(g + 5, 6000);             /* inflate +60 deg */
    sl_put_u16(g + 7, (uint16_t)-8000);  /* vent -80 deg */
    CHECK(acked(request(&l, &c, SL_T_GAIT_SET, 1, g, 9, 0)), "GAIT_SET");
    for (uint8_t ch = 0; ch < 8; ch++)
        CHECK(acked(cfg_ch(&l, &c, ch, 500, 2500, 0, 0, -1000, 1000, 0, 0, (uint8_t)(2 + ch), 0)), "limits +-10");
    request(&l, &c, SL_T_ARM, 10, NULL, 0, 0);
    uint8_t m = SL_MODE_GAIT;
    CHECK(acked(request(&l, &c, SL_T_SET_MODE, 11, &m, 1, 0)), "SET_MODE GAIT");
    uint8_t air[1] = {0x07}; /* cells 0..2 in the air, the rest on the ground: some inflate, some vent */
    request(&l, &c, SL_T_GAIT_CONTACTS, 12, air, 1, 1);
    for (uint32_t t = 10; t <= 200; t += 10)
        sl_link_tick(&l, t);
    int lo = 1500 - 111, hi = 1500 + 111; /* +-10 deg = +-111.1 us */
    for (uint8_t ch = 0; ch < 8; ch++) {
        CHECK(l.out_us[ch] >= lo && l.out_us[ch] <= hi, "GAIT ch%u inside +-10 deg: %u us", ch, l.out_us[ch]);
        CHECK(l.cur[ch] >= -1000 && l.cur[ch] <= 1000, "GAIT ch%u angle %d", ch, l.cur[ch]);
    }
    /* OSC as well: an oscillator accepted under wide limits, then the limits narrowed */
    fake_link(&l, &c, 0);
    request(&l, &c, SL_T_ARM, 1, NULL, 0, 0);
    uint8_t o[9] = {0};
    sl_put_u16(o + 1, 6000);
    sl_put_u16(o + 5, 1000);
    CHECK(acked(request(&l, &c, SL_T_OSC_SET, 2, o, 9, 0)), "OSC_SET 60 deg");
    CHECK(acked(cfg_ch(&l, &c, 0, 500, 2500, 0, 0, -1000, 1000, 0, 0, 3, 0)), "limits +-10");
    m = SL_MODE_OSC;
    request(&l, &c, SL_T_SET_MODE, 4, &m, 1, 0);
    int worst = 0;
    for (uint32_t t = 1; t <= 1000; t++) {
        if (t % 100 == 0)
            request(&l, &c, SL_T_PING, (uint8_t)(5 + t / 100), NULL, 0, t);
        sl_link_tick(&l, t);
        int d = abs((int)l.out_us[0] - 1500);
        if (d > worst)
            worst = d;
    }
    CHECK(worst <= 111 && worst >= 100, "OSC inside +-10 deg (and reaching it): %d us", worst);
}

/* defect 4: HOLD changed the output after SET_PULSES (2300 -> 1500 us); PROTOCOL.md section 6: HOLD keeps the last
 * pulse. PARK then ramps from that pulse (not a jump) to the park angle. */
static void test_hold_keeps_override(void)
{
    sl_link_t l;
    capture_t c;
    fake_link(&l, &c, 0);
    uint8_t cl[6];
    sl_put_u16(cl, 200);
    sl_put_u16(cl + 2, 300);
    sl_put_u16(cl + 4, 2000);
    request(&l, &c, SL_T_CONFIG_LINK, 1, cl, 6, 0);
    request(&l, &c, SL_T_ARM, 2, NULL, 0, 0);
    uint8_t p[6] = {0, 2};
    sl_put_u16(p + 2, 2300);
    sl_put_u16(p + 4, 800);
    CHECK(acked(request(&l, &c, SL_T_SET_PULSES, 3, p, 6, 0)), "SET_PULSES");
    CHECK(l.out_us[0] == 2300 && l.out_us[1] == 800, "override %u %u", l.out_us[0], l.out_us[1]);
    uint32_t t = 1;
    int held = 1, jumps = 0;
    uint16_t prev0 = l.out_us[0];
    for (; t <= 1600; t++) {
        sl_link_tick(&l, t);
        if (l.state == SL_ST_HOLD && (l.out_us[0] != 2300 || l.out_us[1] != 800))
            held = 0;
        if (abs((int)l.out_us[0] - prev0) > 12) /* 90 deg/s: 0.9 deg = 10 us per 10 ms step */
            jumps++;
        prev0 = l.out_us[0];
    }
    CHECK(held, "HOLD kept the override pulses");
    CHECK(l.state == SL_ST_PARK, "state %u", l.state);
    CHECK(jumps == 0, "PARK ramps from the held pulse (%d jumps)", jumps);
    CHECK(l.out_us[0] == 1500 && l.out_us[1] == 1500, "parked at 0 deg: %u %u", l.out_us[0], l.out_us[1]);
}

/* the same sequence with a slew limit and an inverted, trimmed channel: the ramp starts at the held pulse */
static void test_park_from_override_inverted(void)
{
    sl_link_t l;
    capture_t c;
    fake_link(&l, &c, 0);
    CHECK(acked(cfg_ch(&l, &c, 0, 1000, 2000, 300, 1, -6000, 6000, 1500, 45, 1, 0)), "CONFIG_CH");
    request(&l, &c, SL_T_ARM, 2, NULL, 0, 0);
    uint8_t p[4] = {0, 1};
    sl_put_u16(p + 2, 1200);
    CHECK(acked(request(&l, &c, SL_T_SET_PULSES, 3, p, 4, 0)), "SET_PULSES 1200");
    CHECK(l.out_us[0] == 1200, "override %u", l.out_us[0]);
    uint16_t prev = 1200;
    int jumps = 0, held = 1;
    for (uint32_t t = 1; t <= 6000; t++) {
        sl_link_tick(&l, t);
        if (l.out_us[0] && abs((int)l.out_us[0] - prev) > 3)
            jumps++;
        if (l.out_us[0])
            prev = l.out_us[0];
        if (l.state == SL_ST_HOLD && l.out_us[0] != 1200)
            held = 0;
    }
    CHECK(held, "HOLD kept 1200 us");
    /* park 15 deg, inverted, trim 3 deg: a = -15 + 3 = -12 deg -> 1500 - 12 * 1000 / 180 = 1433.3 us */
    CHECK(prev == 1433, "parked at %u", prev);
    CHECK(jumps == 0, "%d jumps", jumps);
}

/* OSC with joint gains (13-byte OSC_SET): a sine in D drives a joint that closes by 15 deg and opens by 60 deg per
 * 30 deg of v, i.e. the two half-waves have their own amplitudes; the swing check uses the mapped ends */
static void test_osc_gains(void)
{
    sl_link_t l;
    capture_t c;
    fake_link(&l, &c, 0);
    request(&l, &c, SL_T_ARM, 1, NULL, 0, 0);
    uint8_t o[13] = {0};
    sl_put_u16(o + 1, 3000);           /* v amplitude 30 "deg" */
    sl_put_u16(o + 5, 1000);           /* 1 s */
    sl_put_u16(o + 9, 8192);           /* gain 0.5 for v >= 0 */
    sl_put_u16(o + 11, (uint16_t)32767); /* gain ~2 for v < 0 */
    CHECK(acked(request(&l, &c, SL_T_OSC_SET, 2, o, 13, 0)), "OSC_SET with gains");
    sl_put_u16(o + 11, (uint16_t)-16384);
    sl_packet_t *r = request(&l, &c, SL_T_OSC_SET, 3, o, 13, 0);
    CHECK(r && r->type == SL_T_NAK && r->payload[1] == 5, "gains of both signs refused");
    sl_put_u16(o + 11, (uint16_t)32767);
    CHECK(acked(cfg_ch(&l, &c, 1, 500, 2500, 0, 0, -5000, 9000, 0, 0, 4, 0)), "ch1 limits -50..90");
    o[0] = 1;
    r = request(&l, &c, SL_T_OSC_SET, 5, o, 13, 0);
    CHECK(r && r->type == SL_T_NAK && r->payload[1] == 2, "mapped swing -60 deg outside -50 refused");
    uint8_t m = SL_MODE_OSC;
    request(&l, &c, SL_T_SET_MODE, 6, &m, 1, 0);
    int lo = 9999, hi = 0;
    for (uint32_t t = 1; t <= 1000; t++) {
        if (t % 100 == 0)
            request(&l, &c, SL_T_PING, (uint8_t)(7 + t / 100), NULL, 0, t);
        sl_link_tick(&l, t);
        if (l.out_us[0] < lo)
            lo = l.out_us[0];
        if (l.out_us[0] > hi)
            hi = l.out_us[0];
    }
    /* +15 deg -> 1666.7 us, -60 deg -> 833.3 us (within one us of rounding) */
    CHECK(abs(hi - 1667) <= 1 && abs(lo - 833) <= 1, "half-waves %d..%d us", lo, hi);
}

int main(void)
{
    test_osc_gains();
    test_config_while_disarmed();
    test_override_narrowed();
    test_gait_obeys_later_limits();
    test_hold_keeps_override();
    test_park_from_override_inverted();
    return check_summary("test_outputs");
}
