/* Per-channel servo calibration and limits: joint angle (centidegrees) -> pulse width (us).
 * Portable C99 (host tests and AVR). */
#ifndef SL_SERVO_H
#define SL_SERVO_H

#include <stdint.h>

#define SL_CDEG_MAX 9000   /* commanded angles live in [-90, 90] degrees */
#define SL_US_ABS_MIN 400  /* absolute bounds of a configured pulse range */
#define SL_US_ABS_MAX 2600

typedef struct {
    uint16_t min_us;       /* pulse at -90 degrees (before trim/invert), default 500 */
    uint16_t max_us;       /* pulse at +90 degrees, default 2500 */
    int16_t trim_cdeg;     /* added after invert (mechanical zero offset) */
    uint8_t invert;        /* 1: the servo turns the other way */
    int16_t lo_cdeg;       /* soft limits of the commanded joint angle */
    int16_t hi_cdeg;
    int16_t park_cdeg;     /* where the watchdog parks the joint */
    uint16_t max_slew_dps; /* degrees per second, 0 = unlimited */
} sl_chan_cfg_t;

void sl_chan_cfg_default(sl_chan_cfg_t *c);

/* Check a configuration; returns 0 if valid, else the 1-based index of the first bad field
 * (1 min_us, 2 max_us, 3 trim, 4 invert, 5 lo, 6 hi, 7 park, 8 slew), used as NAK detail. */
uint8_t sl_chan_cfg_check(const sl_chan_cfg_t *c);

/* Clamp a commanded angle to the channel's soft limits; *clamped set to 1 if it moved. */
int16_t sl_limit_cdeg(const sl_chan_cfg_t *c, int16_t cdeg, uint8_t *clamped);

/* Joint angle (already within limits) -> pulse width (see PROTOCOL.md "Angle to pulse"), then
 * clamped to [min_us, max_us] (sets *clamped). */
uint16_t sl_cdeg_to_us(const sl_chan_cfg_t *c, int16_t cdeg, uint8_t *clamped);

/* 1 if the pulse of this (limited) angle leaves [min_us, max_us], i.e. |(invert ? -a : a) + trim| > 90 deg:
 * what sl_cdeg_to_us would clamp, without its division. */
uint8_t sl_pulse_clamps(const sl_chan_cfg_t *c, int16_t cdeg);

/* The pulse window of a channel: the widths of its soft limits lo and hi (in either order, an inverted servo
 * swaps them), inside [min_us, max_us]. Every pulse the link outputs lies in it. */
void sl_pulse_window(const sl_chan_cfg_t *c, uint16_t *lo_us, uint16_t *hi_us);

/* Inverse of sl_cdeg_to_us: the joint angle (centidegrees, inside the soft limits) whose pulse is closest to us.
 * Used when a SET_PULSES override hands over to an angle (PARK, ARM, SET_MODE) without a jump. */
int16_t sl_us_to_cdeg(const sl_chan_cfg_t *c, uint16_t us);

/* Move cur towards target by at most max_slew_dps * dt_ms (centidegrees); unlimited if 0. */
int16_t sl_slew(int16_t cur, int16_t target, uint16_t max_slew_dps, uint16_t dt_ms);

/* PCA9685 (25 MHz oscillator) helpers for the optional I2C back end. */
uint8_t sl_pca9685_prescale(uint16_t freq_hz);                  /* round(25e6 / (4096 f)) - 1 */
uint16_t sl_pca9685_off_count(uint16_t us, uint8_t prescale);   /* 12-bit OFF count for a pulse */

#endif
