#include "osc.h"

#ifdef __AVR__
#include <avr/pgmspace.h>
#define SL_TABLE const uint16_t PROGMEM
#define SL_READ(p) pgm_read_word(p)
#else
#define SL_TABLE static const uint16_t
#define SL_READ(p) (*(p))
#endif

/* round(32767 * sin(pi/2 * k / 64)), k = 0..64 */
SL_TABLE sl_quarter[65] = {
    0, 804, 1608, 2410, 3212, 4011, 4808, 5602, 6393, 7179,
    7962, 8739, 9512, 10278, 11039, 11793, 12539, 13279, 14010, 14732,
    15446, 16151, 16846, 17530, 18204, 18868, 19519, 20159, 20787, 21403,
    22005, 22594, 23170, 23731, 24279, 24811, 25329, 25832, 26319, 26790,
    27245, 27683, 28105, 28510, 28898, 29268, 29621, 29956, 30273, 30571,
    30852, 31113, 31356, 31580, 31785, 31971, 32137, 32285, 32412, 32521,
    32609, 32678, 32728, 32757, 32767
};

int16_t sl_sin16(uint16_t phase)
{
    uint8_t quadrant = (uint8_t)(phase >> 14);
    uint16_t x = phase & 0x3FFF; /* position inside the quadrant: 0..16383 */
    if (quadrant & 1)
        x = (uint16_t)(0x4000 - x); /* mirrored: 1..16384 */
    uint8_t k = (uint8_t)(x >> 8);  /* 0..64 */
    uint8_t f = (uint8_t)(x & 0xFF);
    int32_t a = (int32_t)SL_READ(&sl_quarter[k]);
    int32_t b = k < 64 ? (int32_t)SL_READ(&sl_quarter[k + 1]) : a;
    int32_t v = a + (((b - a) * f + 128) >> 8);
    return (int16_t)((quadrant & 2) ? -v : v);
}

int16_t sl_osc_value(const sl_osc_t *o, uint32_t t_ms)
{
    if (o->period_ms == 0 || o->amp_cdeg == 0)
        return o->offset_cdeg;
    uint32_t tm = t_ms % o->period_ms;
    uint16_t ph = (uint16_t)((tm << 16) / o->period_ms);              /* tm < 65536: fits */
    ph = (uint16_t)(ph + (uint16_t)(((uint32_t)o->phase_cdeg << 16) / 36000UL));
    int32_t s = sl_sin16(ph);
    int32_t v = (int32_t)o->offset_cdeg + ((int32_t)o->amp_cdeg * s + (s >= 0 ? 16384 : -16384)) / 32767;
    if (v > 32767)
        v = 32767;
    if (v < -32768)
        v = -32768;
    return (int16_t)v;
}

int16_t sl_osc_gain(const sl_osc_t *o, int16_t v)
{
    int32_t g = v >= 0 ? o->gain_pos : o->gain_neg;
    int32_t x = (int32_t)v * g;
    x = x >= 0 ? (x + SL_GAIN_ONE / 2) / SL_GAIN_ONE : -((-x + SL_GAIN_ONE / 2) / SL_GAIN_ONE);
    return (int16_t)x;
}
