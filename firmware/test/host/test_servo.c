/* Angle -> pulse mapping, limits, slew, PCA9685 math and the fixed-point sine generator. */
#define _DEFAULT_SOURCE
#include <math.h>
#include <stdlib.h>

#include "common.h"

static void test_vectors(const jnode_t *root)
{
    int n = 0;
    for (jnode_t *v = json_get(root, "angle_to_us")->child; v; v = v->next, n++) {
        sl_chan_cfg_t c;
        sl_chan_cfg_default(&c);
        c.min_us = (uint16_t)json_int(v, "min_us", c.min_us);
        c.max_us = (uint16_t)json_int(v, "max_us", c.max_us);
        c.trim_cdeg = (int16_t)json_int(v, "trim_cdeg", 0);
        c.invert = (uint8_t)json_int(v, "invert", 0);
        uint8_t cl = 0;
        uint16_t us = sl_cdeg_to_us(&c, (int16_t)json_int(v, "cdeg", 0), &cl);
        CHECK(us == json_int(v, "us", -1) && cl == json_int(v, "clamped", -1), "%s: %u us clamped %u",
              json_str(v, "name"), us, cl);
    }
    CHECK(n >= 10, "angle vectors %d", n);
    for (jnode_t *v = json_get(root, "limits")->child; v; v = v->next) {
        sl_chan_cfg_t c;
        sl_chan_cfg_default(&c);
        c.lo_cdeg = (int16_t)json_int(v, "lo_cdeg", 0);
        c.hi_cdeg = (int16_t)json_int(v, "hi_cdeg", 0);
        uint8_t cl = 0;
        int16_t o = sl_limit_cdeg(&c, (int16_t)json_int(v, "cdeg", 0), &cl);
        CHECK(o == json_int(v, "out", 0) && cl == json_int(v, "clamped", -1), "limit %s", json_str(v, "name"));
    }
    for (jnode_t *v = json_get(root, "pca9685")->child; v; v = v->next) {
        if (json_get(v, "freq_hz"))
            CHECK(sl_pca9685_prescale((uint16_t)json_int(v, "freq_hz", 0)) == json_int(v, "prescale", -1), "prescale");
        else
            CHECK(sl_pca9685_off_count((uint16_t)json_int(v, "us", 0), (uint8_t)json_int(v, "prescale", 0)) ==
                      json_int(v, "count", -1),
                  "pca count for %ld us", json_int(v, "us", 0));
    }
}

/* the integer mapping agrees with the real-valued formula everywhere to within half a microsecond */
static void test_mapping_sweep(void)
{
    sl_chan_cfg_t c;
    sl_chan_cfg_default(&c);
    double worst = 0;
    for (int inv = 0; inv < 2; inv++)
        for (int a = -9000; a <= 9000; a += 7) {
            c.invert = (uint8_t)inv;
            c.trim_cdeg = 0;
            uint8_t cl = 0;
            uint16_t us = sl_cdeg_to_us(&c, (int16_t)a, &cl);
            double exact = 1500.0 + (inv ? -a : a) / 9000.0 * 1000.0;
            double err = fabs(us - exact);
            if (err > worst)
                worst = err;
            CHECK(!cl, "clamped at %d", a);
        }
    CHECK(worst <= 0.5 + 1e-9, "worst mapping error %.3f us", worst);
}

/* the cheap clamp predicate agrees with the mapping's own clamping except in the half-microsecond band
 * just past +-90 deg, where the rounded pulse equals the range end and the predicate still reports */
static void test_clamp_predicate(void)
{
    sl_chan_cfg_t c;
    sl_chan_cfg_default(&c);
    int disagree = 0;
    for (int trim = -2000; trim <= 2000; trim += 250)
        for (int inv = 0; inv < 2; inv++)
            for (int a = -9000; a <= 9000; a += 11) {
                c.trim_cdeg = (int16_t)trim;
                c.invert = (uint8_t)inv;
                uint8_t cl = 0;
                sl_cdeg_to_us(&c, (int16_t)a, &cl);
                int e = (inv ? -a : a) + trim;
                if (cl != sl_pulse_clamps(&c, (int16_t)a) && !(abs(e) > 9000 && abs(e) <= 9004))
                    disagree++;
            }
    CHECK(disagree == 0, "%d disagreements", disagree);
}

static void test_config_check(void)
{
    sl_chan_cfg_t c;
    sl_chan_cfg_default(&c);
    CHECK(sl_chan_cfg_check(&c) == 0, "default config valid");
    c.min_us = 399;
    CHECK(sl_chan_cfg_check(&c) == 1, "min_us 399");
    sl_chan_cfg_default(&c);
    c.max_us = 2601;
    CHECK(sl_chan_cfg_check(&c) == 2, "max_us 2601");
    sl_chan_cfg_default(&c);
    c.lo_cdeg = 100;
    c.hi_cdeg = 0;
    CHECK(sl_chan_cfg_check(&c) == 5, "lo > hi");
    sl_chan_cfg_default(&c);
    c.lo_cdeg = -1000;
    c.hi_cdeg = 1000;
    c.park_cdeg = 2000;
    CHECK(sl_chan_cfg_check(&c) == 7, "park outside limits");
}

static void test_slew(void)
{
    /* 60 deg/s for 100 ms = 6 deg = 600 cdeg, in either direction, never overshooting */
    CHECK(sl_slew(0, 9000, 60, 100) == 600, "slew up");
    CHECK(sl_slew(0, -9000, 60, 100) == -600, "slew down");
    CHECK(sl_slew(0, 300, 60, 100) == 300, "no overshoot");
    CHECK(sl_slew(-100, 9000, 0, 10) == 9000, "unlimited");
    /* integrating 10 ms steps reaches the target at the closed-form time: 90 deg at 45 deg/s = 2 s */
    int16_t cur = 0;
    int steps = 0;
    while (cur != 9000 && steps < 1000) {
        cur = sl_slew(cur, 9000, 45, 10);
        steps++;
    }
    CHECK(steps == 200, "90 deg at 45 deg/s took %d x 10 ms", steps);
}

static void test_osc(void)
{
    double worst = 0;
    for (uint32_t ph = 0; ph < 65536; ph += 13) {
        double s = sl_sin16((uint16_t)ph) / 32767.0;
        double e = fabs(s - sin(2 * M_PI * ph / 65536.0));
        if (e > worst)
            worst = e;
    }
    CHECK(worst < 2e-4, "sine table error %.2e", worst);
    sl_osc_t o = {4500, -1000, 2000, 9000, SL_GAIN_ONE, SL_GAIN_ONE}; /* 45 deg amplitude, -10 deg offset, 2 s period, 90 deg phase */
    double worst_cdeg = 0;
    for (uint32_t t = 0; t < 6000; t += 3) {
        double exact = -1000 + 4500 * sin(2 * M_PI * t / 2000.0 + M_PI / 2);
        double e = fabs(sl_osc_value(&o, t) - exact);
        if (e > worst_cdeg)
            worst_cdeg = e;
    }
    CHECK(worst_cdeg <= 3.0, "oscillator error %.2f cdeg", worst_cdeg);
    sl_osc_t z = {0, 1234, 1000, 0, SL_GAIN_ONE, SL_GAIN_ONE};
    CHECK(sl_osc_value(&z, 777) == 1234, "zero amplitude = offset");
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: test_servo protocol.json\n");
        return 2;
    }
    jnode_t *root = json_load(argv[1]);
    CHECK(root != NULL, "vectors");
    if (root)
        test_vectors(root);
    test_mapping_sweep();
    test_config_check();
    test_clamp_predicate();
    test_slew();
    test_osc();
    return check_summary("test_servo");
}
