/* The device-side link: request/reply exchanges from the shared vectors, ARM gating, clamping,
 * "never partially applied", the HOLD -> PARK -> RELEASE watchdog with a fake clock, slew, OSC mode. */
#define _DEFAULT_SOURCE
#include <math.h>
#include <stdlib.h>

#include "common.h"

static uint32_t sl_get_u32_test(const uint8_t *p)
{
    return (uint32_t)p[0] | ((uint32_t)p[1] << 8) | ((uint32_t)p[2] << 16) | ((uint32_t)p[3] << 24);
}

static void arm(sl_link_t *l, capture_t *c, uint32_t now)
{
    sl_packet_t *r = request(l, c, SL_T_ARM, 1, NULL, 0, now);
    CHECK(r && r->type == SL_T_ACK && r->payload[1] == SL_ST_ARMED, "ARM acked");
}

static void test_exchanges(const jnode_t *root)
{
    int n = 0;
    for (jnode_t *v = json_get(root, "exchanges")->child; v; v = v->next, n++) {
        sl_link_t l;
        capture_t c;
        fake_link(&l, &c, 0);
        if (json_int(v, "armed", 0))
            arm(&l, &c, 0);
        int before = c.n;
        uint8_t buf[300];
        if (json_get(v, "raw_hex")) {
            int m = vec_bytes(v, "raw_hex", buf, sizeof buf);
            for (int i = 0; i < m; i++)
                sl_link_feed(&l, buf[i], 1);
        } else {
            int m = vec_bytes(v, "payload_hex", buf, sizeof buf);
            request(&l, &c, (uint8_t)json_int(v, "type", 0), (uint8_t)json_int(v, "seq", 0), buf, (uint8_t)m, 1);
        }
        const jnode_t *want = json_get(v, "reply");
        const char *name = json_str(v, "name");
        CHECK(c.n == before + 1, "%s: %d replies", name, c.n - before);
        if (c.n != before + 1)
            continue;
        sl_packet_t *r = &c.pkt[c.n - 1];
        CHECK(r->type == json_int(want, "type", -1), "%s: reply type 0x%02x", name, r->type);
        CHECK(r->seq == json_int(want, "seq", -1), "%s: reply seq %u", name, r->seq);
        if (json_get(want, "code"))
            CHECK(r->payload[0] == json_int(want, "code", -1), "%s: NAK code %u", name, r->payload[0]);
        if (json_get(want, "detail"))
            CHECK(r->payload[1] == json_int(want, "detail", -1), "%s: NAK detail %u", name, r->payload[1]);
        if (json_get(want, "request"))
            CHECK(r->payload[0] == json_int(want, "request", -1) && r->payload[1] == json_int(want, "state", -1),
                  "%s: ACK request/state", name);
        if (json_get(want, "data_hex")) {
            int m = vec_bytes(want, "data_hex", buf, sizeof buf);
            CHECK(r->plen == 2 + m && !memcmp(r->payload + 2, buf, (size_t)m), "%s: ACK data", name);
        }
    }
    CHECK(n >= 10, "exchange vectors %d", n);
}

static void test_boot_and_hello(void)
{
    sl_link_t l;
    capture_t c;
    fake_link(&l, &c, 0);
    CHECK(c.n == 1 && c.pkt[0].type == SL_T_HELLO_ACK && c.pkt[0].seq == 0, "boot HELLO_ACK");
    CHECK(c.pkt[0].plen == 15 && c.pkt[0].payload[0] == SL_PROTO_MAJOR && c.pkt[0].payload[5] == 8 &&
              sl_get_u16(c.pkt[0].payload + 7) == 500,
          "HELLO_ACK fields");
    for (int ch = 0; ch < 8; ch++)
        CHECK(l.out_us[ch] == 0, "no pulses before ARM");
}

static void test_arm_clamp_atomic(void)
{
    sl_link_t l;
    capture_t c;
    fake_link(&l, &c, 0);
    /* channel 1 limited to +-30 deg */
    uint8_t cfg[16] = {1};
    sl_put_u16(cfg + 1, 500);
    sl_put_u16(cfg + 3, 2500);
    sl_put_u16(cfg + 5, 0);
    cfg[7] = 0;
    sl_put_u16(cfg + 8, (uint16_t)-3000);
    sl_put_u16(cfg + 10, 3000);
    sl_put_u16(cfg + 12, 0);
    sl_put_u16(cfg + 14, 0);
    sl_packet_t *r = request(&l, &c, SL_T_CONFIG_CH, 2, cfg, 16, 0);
    CHECK(r && r->type == SL_T_ACK, "CONFIG_CH acked");
    arm(&l, &c, 0);
    for (int ch = 0; ch < 8; ch++)
        CHECK(l.out_us[ch] == 1500, "armed at the park angle: ch%d %u", ch, l.out_us[ch]);
    uint8_t p[2 + 6] = {0, 3};
    sl_put_u16(p + 2, 4500);
    sl_put_u16(p + 4, 4500);
    sl_put_u16(p + 6, (uint16_t)-9000);
    r = request(&l, &c, SL_T_SET_ANGLES, 3, p, 8, 5);
    CHECK(r && r->type == SL_T_ACK && sl_get_u16(r->payload + 2) == 0x0002 && r->payload[4] == 3, "clamp mask");
    CHECK(l.out_us[0] == 2000 && l.out_us[1] == 1833 && l.out_us[2] == 500, "pulses %u %u %u", l.out_us[0],
          l.out_us[1], l.out_us[2]);
    /* one bad value: nothing at all changes */
    uint8_t q[2 + 4] = {0, 2};
    sl_put_u16(q + 2, 0);
    sl_put_u16(q + 4, 9500);
    r = request(&l, &c, SL_T_SET_ANGLES, 4, q, 6, 6);
    CHECK(r && r->type == SL_T_NAK && r->payload[0] == SL_E_RANGE && r->payload[1] == 1, "range NAK");
    CHECK(l.out_us[0] == 2000 && l.out_us[1] == 1833, "not partially applied");
    /* DISARM: pulses stop, motion refused */
    r = request(&l, &c, SL_T_DISARM, 5, NULL, 0, 7);
    CHECK(r && r->type == SL_T_ACK && r->payload[1] == SL_ST_DISARMED, "DISARM");
    for (int ch = 0; ch < 8; ch++)
        CHECK(l.out_us[ch] == 0, "disarmed ch%d", ch);
    r = request(&l, &c, SL_T_SET_ANGLES, 6, q, 4 + 0 * 2 + 2, 8);
    CHECK(r && r->type == SL_T_NAK, "SET_ANGLES after DISARM");
    /* GET_STATE reports the outputs */
    r = request(&l, &c, SL_T_GET_STATE, 7, NULL, 0, 9);
    CHECK(r && r->type == SL_T_ACK && r->plen == 4 + 16 && r->payload[3] == 8, "GET_STATE");
    /* PING counts: 8 valid frames with this one; two sequence gaps (ARM used seq 1 after 2, then 3 after 1) */
    r = request(&l, &c, SL_T_PING, 8, NULL, 0, 10);
    CHECK(r && r->type == SL_T_ACK && r->plen == 18 && sl_get_u16(r->payload + 6) == 8, "PING rx_ok %u",
          r ? sl_get_u16(r->payload + 6) : 0);
    CHECK(r && sl_get_u16(r->payload + 12) == 2, "seq gaps %u", r ? sl_get_u16(r->payload + 12) : 0);
    CHECK(r && r->payload[16] == 0 && r->payload[17] == 0, "no servo faults");
    /* servo back-end faults: one EVENT SERVO_FAULT per run of failures, every failure counted in PING */
    int before = c.n;
    sl_link_servo_status(&l, 0, 11);
    sl_link_servo_status(&l, 0, 12);
    CHECK(c.n == before + 1 && c.pkt[before].type == SL_T_EVENT && c.pkt[before].payload[0] == SL_EV_SERVO_FAULT,
          "one SERVO_FAULT event for a run of failures");
    sl_link_servo_status(&l, 1, 13);
    sl_link_servo_status(&l, 0, 14);
    CHECK(c.n == before + 2 && c.pkt[before + 1].payload[0] == SL_EV_SERVO_FAULT, "a new run: a new event");
    r = request(&l, &c, SL_T_PING, 9, NULL, 0, 15);
    CHECK(r && r->type == SL_T_ACK && r->payload[16] == 1 && r->payload[17] == 3, "PING servo fault %u, count %u",
          r ? r->payload[16] : 0, r ? r->payload[17] : 0);
}

static void test_watchdog(void)
{
    sl_link_t l;
    capture_t c;
    fake_link(&l, &c, 1000);
    uint8_t cl[6];
    sl_put_u16(cl, 200);  /* watchdog 200 ms */
    sl_put_u16(cl + 2, 300); /* hold 300 ms, then park */
    sl_put_u16(cl + 4, 1000); /* release 1 s after parking */
    sl_packet_t *r = request(&l, &c, SL_T_CONFIG_LINK, 1, cl, 6, 1000);
    CHECK(r && r->type == SL_T_ACK, "CONFIG_LINK");
    r = request(&l, &c, SL_T_ARM, 2, NULL, 0, 1000);
    uint8_t p[4] = {0, 1};
    sl_put_u16(p + 2, 9000);
    r = request(&l, &c, SL_T_SET_ANGLES, 3, p, 4, 1000);
    CHECK(r && r->type == SL_T_ACK && l.out_us[0] == 2500, "at +90");
    uint32_t t_hold = 0, t_park = 0, t_rel = 0, t_at_park = 0;
    int events = c.n;
    for (uint32_t t = 1000; t <= 4000; t++) {
        sl_link_tick(&l, t);
        if (!t_hold && l.state == SL_ST_HOLD)
            t_hold = t;
        if (!t_park && l.state == SL_ST_PARK)
            t_park = t;
        if (!t_rel && l.state == SL_ST_RELEASED)
            t_rel = t;
        if (!t_at_park && l.state == SL_ST_PARK && l.out_us[0] == 1500)
            t_at_park = t;
        if (l.state == SL_ST_HOLD)
            CHECK(l.out_us[0] == 2500, "HOLD keeps the pulse (%u at %u)", l.out_us[0], t);
    }
    CHECK(t_hold == 1201, "HOLD at %u", t_hold);
    CHECK(t_park == 1501, "PARK at %u", t_park);
    /* park ramps at 90 deg/s (no slew limit configured): 90 deg in 1 s, in 10 ms steps */
    CHECK(t_at_park >= 2490 && t_at_park <= 2520, "parked at %u", t_at_park);
    CHECK(t_rel == 2501, "RELEASE at %u", t_rel);
    CHECK(l.out_us[0] == 0 && l.out_us[7] == 0, "released: no pulses");
    CHECK(c.n == events + 3 && c.pkt[events].type == SL_T_EVENT && c.pkt[events].payload[0] == SL_EV_HOLD &&
              c.pkt[events + 1].payload[0] == SL_EV_PARK && c.pkt[events + 2].payload[0] == SL_EV_RELEASE,
          "three events");
    CHECK(sl_get_u32_test(c.pkt[events].payload + 2) == 1201 && sl_get_u32_test(c.pkt[events + 2].payload + 2) == 2501,
          "event timestamps");
    /* motion needs an explicit ARM again */
    r = request(&l, &c, SL_T_SET_ANGLES, 4, p, 4, 4001);
    CHECK(r && r->type == SL_T_NAK && r->payload[0] == SL_E_NOT_ARMED && r->payload[1] == SL_ST_RELEASED,
          "NOT_ARMED after the watchdog");
    r = request(&l, &c, SL_T_ARM, 5, NULL, 0, 4002);
    r = request(&l, &c, SL_T_SET_ANGLES, 6, p, 4, 4003);
    CHECK(r && r->type == SL_T_ACK && l.out_us[0] == 2500, "resumes after ARM");
    /* a steady 50 Hz stream never trips the watchdog */
    for (uint32_t t = 4003; t < 8000; t++) {
        if (t % 20 == 0)
            request(&l, &c, SL_T_PING, (uint8_t)(7 + (t / 20) % 200), NULL, 0, t);
        sl_link_tick(&l, t);
    }
    CHECK(l.state == SL_ST_ARMED, "state %u after a steady stream", l.state);
}

static void test_slew_link(void)
{
    sl_link_t l;
    capture_t c;
    fake_link(&l, &c, 0);
    uint8_t cfg[16] = {0};
    sl_put_u16(cfg + 1, 500);
    sl_put_u16(cfg + 3, 2500);
    sl_put_u16(cfg + 8, (uint16_t)-9000);
    sl_put_u16(cfg + 10, 9000);
    sl_put_u16(cfg + 14, 90); /* 90 deg/s */
    request(&l, &c, SL_T_CONFIG_CH, 1, cfg, 16, 0);
    request(&l, &c, SL_T_ARM, 2, NULL, 0, 0);
    uint8_t p[4] = {0, 1};
    sl_put_u16(p + 2, 4500);
    request(&l, &c, SL_T_SET_ANGLES, 3, p, 4, 0);
    CHECK(l.out_us[0] == 1500, "slew starts at the old angle");
    uint32_t reached = 0;
    for (uint32_t t = 1; t <= 1000; t++) {
        if (t % 20 == 0)
            request(&l, &c, SL_T_PING, (uint8_t)(4 + t / 20), NULL, 0, t);
        sl_link_tick(&l, t);
        if (!reached && l.out_us[0] == 2000)
            reached = t;
        if (t == 250)
            CHECK(abs((int)l.out_us[0] - 1750) <= 12, "half way at 250 ms: %u", l.out_us[0]);
    }
    CHECK(reached >= 490 && reached <= 510, "45 deg at 90 deg/s reached at %u ms", reached);
}

static void test_osc_mode(void)
{
    sl_link_t l;
    capture_t c;
    fake_link(&l, &c, 0);
    request(&l, &c, SL_T_ARM, 1, NULL, 0, 0);
    uint8_t o[9] = {2};
    sl_put_u16(o + 1, 3000);   /* 30 deg */
    sl_put_u16(o + 3, 1000);   /* +10 deg */
    sl_put_u16(o + 5, 1000);   /* 1 s */
    sl_put_u16(o + 7, 0);
    sl_packet_t *r = request(&l, &c, SL_T_OSC_SET, 2, o, 9, 0);
    CHECK(r && r->type == SL_T_ACK, "OSC_SET");
    sl_put_u16(o + 1, 8500); /* 85 + 10 deg swing leaves the limits */
    r = request(&l, &c, SL_T_OSC_SET, 3, o, 9, 0);
    CHECK(r && r->type == SL_T_NAK && r->payload[0] == SL_E_RANGE && r->payload[1] == 2, "OSC swing past limit");
    uint8_t m = SL_MODE_OSC;
    r = request(&l, &c, SL_T_SET_MODE, 4, &m, 1, 100);
    CHECK(r && r->type == SL_T_ACK, "SET_MODE OSC");
    uint8_t p[4] = {0, 1, 0, 0};
    r = request(&l, &c, SL_T_SET_ANGLES, 5, p, 4, 101);
    CHECK(r && r->type == SL_T_NAK && r->payload[0] == SL_E_MODE, "SET_ANGLES refused in OSC mode");
    double worst = 0;
    for (uint32_t t = 100; t < 2100; t++) {
        if (t % 20 == 0)
            request(&l, &c, SL_T_PING, (uint8_t)(6 + (t / 20) % 200), NULL, 0, t);
        sl_link_tick(&l, t);
        if (t % 10 == 0) { /* the generator is sampled every 10 ms */
            double a = 1000 + 3000 * sin(2 * M_PI * (t - 100) / 1000.0);
            double us = 1500 + a / 9000.0 * 1000.0;
            double e = fabs(l.out_us[2] - us);
            if (e > worst)
                worst = e;
        }
    }
    CHECK(worst <= 1.0, "OSC pulse error %.2f us", worst);
    CHECK(l.out_us[0] == 1500, "channel without oscillator holds");
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: test_link protocol.json\n");
        return 2;
    }
    jnode_t *root = json_load(argv[1]);
    CHECK(root != NULL, "vectors");
    if (root)
        test_exchanges(root);
    test_boot_and_hello();
    test_arm_clamp_atomic();
    test_watchdog();
    test_slew_link();
    test_osc_mode();
    return check_summary("test_link");
}
