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
} sl_osc_t;

/* sin of a 16-bit phase (65536 = one turn), Q15 (-32767..32767), table + linear interpolation */
int16_t sl_sin16(uint16_t phase);

/* Oscillator value in centidegrees at t_ms after its start. */
int16_t sl_osc_value(const sl_osc_t *o, uint32_t t_ms);

#endif
