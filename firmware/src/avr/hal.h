/* Board layer of the ATmega328P firmware (register-level code; never compiled on the host). */
#ifndef SL_HAL_H
#define SL_HAL_H

#include <stdint.h>

#define HAL_N_SERVOS 8

/* Servo back end: the ISR pulse sequencer on D4..D11 (servo_isr.c) or a PCA9685 over I2C
 * (servo_pca9685.c), chosen at build time with `make BACKEND=isr|pca9685`. */
/* Both return 1 on success, 0 when the driver did not take it (PCA9685: no answer on I2C); a failed write is
 * retried, with the driver set up again, at the next call. */
uint8_t hal_servo_init(void);
/* pulse widths in microseconds, 0 = no pulses on that channel */
uint8_t hal_servo_write(const uint16_t *us, uint8_t n);
extern const uint8_t hal_servo_caps; /* SL_CAP_PCA9685 for the I2C back end, else 0 */
/* contact switches for GAIT mode: cell k on A0 + k (PC0..PC5), 6 cells, or 4 (A0..A3) when the I2C back end
 * uses A4, A5 */
extern const uint8_t hal_contact_cells;

#endif
