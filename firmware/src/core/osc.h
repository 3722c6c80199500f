/* On-board sine generator (OSC mode): value = offset + amp * sin(2 pi t / period + phase).
 * Fixed-point, portable C99. */
#ifndef SL_OSC_H
#define SL_OSC_H

#include <stdint.h>

typedef struct {
    int16_t amp_cdeg;
    int16_t offset_cdeg;
    uint16_t period_ms;  /* 0 = constant offset */
    uint16_t phase_cdeg; /* 0..35999 */
    /* joint gains, Q14 (16384 = 1): the angle is g(v) = v * (v >= 0 ? gain_pos : gain_neg) / 16384 of the sine
     * v above, so a joint that closes and opens by different angles per unit of D follows its simulated rotation */
    int16_t gain_pos, gain_neg;
} sl_osc_t;

#define SL_GAIN_ONE 16384

/* g(v) of an oscillator, rounded to nearest (|v| <= 18000, |gain| <= 32767: inside 32 bits) */
int16_t sl_osc_gain(const sl_osc_t *o, int16_t v);

/* sin of a 16-bit phase (65536 = one turn), Q15 (-32767..32767), table + linear interpolation */
int16_t sl_sin16(uint16_t phase);

/* Oscillator value in centidegrees at t_ms after its start. */
int16_t sl_osc_value(const sl_osc_t *o, uint32_t t_ms);

#endif
