#include "servo.h"

void sl_chan_cfg_default(sl_chan_cfg_t *c)
{
    c->min_us = 500;
    c->max_us = 2500;
    c->trim_cdeg = 0;
    c->invert = 0;
    c->lo_cdeg = -SL_CDEG_MAX;
    c->hi_cdeg = SL_CDEG_MAX;
    c->park_cdeg = 0;
    c->max_slew_dps = 0;
}

uint8_t sl_chan_cfg_check(const sl_chan_cfg_t *c)
{
    if (c->min_us < SL_US_ABS_MIN || c->min_us >= c->max_us)
        return 1;
    if (c->max_us > SL_US_ABS_MAX)
        return 2;
    if (c->trim_cdeg < -2000 || c->trim_cdeg > 2000)
        return 3;
    if (c->invert > 1)
        return 4;
    if (c->lo_cdeg < -SL_CDEG_MAX || c->lo_cdeg > c->hi_cdeg)
        return 5;
    if (c->hi_cdeg > SL_CDEG_MAX)
        return 6;
    if (c->park_cdeg < c->lo_cdeg || c->park_cdeg > c->hi_cdeg)
        return 7;
    if (c->max_slew_dps > 3600)
        return 8;
    return 0;
}

int16_t sl_limit_cdeg(const sl_chan_cfg_t *c, int16_t cdeg, uint8_t *clamped)
{
    if (cdeg < c->lo_cdeg) {
        *clamped = 1;
        return c->lo_cdeg;
    }
    if (cdeg > c->hi_cdeg) {
        *clamped = 1;
        return c->hi_cdeg;
    }
    return cdeg;
}

uint16_t sl_cdeg_to_us(const sl_chan_cfg_t *c, int16_t cdeg, uint8_t *clamped)
{
    int32_t a = c->invert ? -(int32_t)cdeg : (int32_t)cdeg;
    a += c->trim_cdeg;
    int32_t span = (int32_t)c->max_us - (int32_t)c->min_us;
    /* us = round_half_up(((min + max) * 9000 + a * span) / 18000): exact integer arithmetic,
     * |a| <= 11000 and span <= 2200 keep every term well inside 32 bits */
    int32_t num = ((int32_t)c->min_us + (int32_t)c->max_us) * 9000 + a * span;
    int32_t us = num < 0 ? 0 : (num + 9000) / 18000;
    if (us < c->min_us) {
        *clamped = 1;
        us = c->min_us;
    }
    if (us > c->max_us) {
        *clamped = 1;
        us = c->max_us;
    }
    return (uint16_t)us;
}

uint8_t sl_pulse_clamps(const sl_chan_cfg_t *c, int16_t cdeg)
{
    int32_t a = (c->invert ? -(int32_t)cdeg : (int32_t)cdeg) + c->trim_cdeg;
    return (uint8_t)(a > SL_CDEG_MAX || a < -SL_CDEG_MAX);
}

void sl_pulse_window(const sl_chan_cfg_t *c, uint16_t *lo_us, uint16_t *hi_us)
{
    uint8_t dummy = 0;
    uint16_t a = sl_cdeg_to_us(c, c->lo_cdeg, &dummy), b = sl_cdeg_to_us(c, c->hi_cdeg, &dummy);
    *lo_us = a < b ? a : b;
    *hi_us = a < b ? b : a;
}

int16_t sl_us_to_cdeg(const sl_chan_cfg_t *c, uint16_t us)
{
    /* a = (2 us - (min + max)) * 9000 / span, rounded to nearest; then undo trim and invert */
    int32_t span = (int32_t)c->max_us - (int32_t)c->min_us;
    int32_t num = (2 * (int32_t)us - (int32_t)c->min_us - (int32_t)c->max_us) * 9000;
    int32_t a = (num >= 0 ? num + span / 2 : num - span / 2) / span;
    a -= c->trim_cdeg;
    if (c->invert)
        a = -a;
    if (a < c->lo_cdeg)
        a = c->lo_cdeg;
    if (a > c->hi_cdeg)
        a = c->hi_cdeg;
    return (int16_t)a;
}

int16_t sl_slew(int16_t cur, int16_t target, uint16_t max_slew_dps, uint16_t dt_ms)
{
    if (max_slew_dps == 0)
        return target;
    int32_t step = ((int32_t)max_slew_dps * dt_ms) / 10; /* deg/s * ms = mdeg; /10 -> cdeg */
    int32_t d = (int32_t)target - cur;
    if (d > step)
        return (int16_t)(cur + step);
    if (d < -step)
        return (int16_t)(cur - step);
    return target;
}

uint8_t sl_pca9685_prescale(uint16_t freq_hz)
{
    uint32_t den = 4096UL * freq_hz;
    uint32_t p = (25000000UL + den / 2) / den; /* rounded */
    if (p < 4)
        p = 4;
    if (p > 256)
        p = 256;
    return (uint8_t)(p - 1);
}

uint16_t sl_pca9685_off_count(uint16_t us, uint8_t prescale)
{
    /* one count lasts (prescale + 1) / 25 MHz = (prescale + 1) / 25 us */
    uint32_t cnt = ((uint32_t)us * 25UL + (prescale + 1) / 2) / (uint32_t)(prescale + 1);
    if (cnt > 4095)
        cnt = 4095;
    return (uint16_t)cnt;
}
