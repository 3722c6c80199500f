/* Optional servo back end: a PCA9685 16-channel PWM driver on I2C (A4 = SDA, A5 = SCL, address 0x40),
 * 50 Hz. Same interface as the ISR sequencer; build with `make BACKEND=pca9685`. Every bus wait is
 * bounded, so a missing board cannot hang the firmware (the link keeps working and reports). */
#include <avr/io.h>
#include <util/twi.h>

#include "../core/link.h"
#include "../core/servo.h"
#include "hal.h"

#define PCA_ADDR 0x40
#define PCA_MODE1 0x00
#define PCA_PRESCALE 0xFE
#define PCA_LED0 0x06

const uint8_t hal_servo_caps = SL_CAP_PCA9685;
const uint8_t hal_contact_cells = 4; /* A4, A5 are the I2C bus */

static uint8_t prescale;
static uint8_t ready;                /* prescaler and wake-up written since the last failure */
static uint16_t last[HAL_N_SERVOS]; /* what the chip holds (0xFFFF = unknown): only successful writes */

static uint8_t twi_wait(void)
{
    for (uint16_t i = 0; i < 2000; i++)
        if (TWCR & (1 << TWINT))
            return 1;
    return 0;
}

static uint8_t twi_start(void)
{
    TWCR = (1 << TWINT) | (1 << TWSTA) | (1 << TWEN);
    if (!twi_wait())
        return 0;
    uint8_t st = TW_STATUS;
    return st == TW_START || st == TW_REP_START;
}

static uint8_t twi_write(uint8_t b)
{
    TWDR = b;
    TWCR = (1 << TWINT) | (1 << TWEN);
    if (!twi_wait())
        return 0;
    uint8_t st = TW_STATUS;
    return st == TW_MT_SLA_ACK || st == TW_MT_DATA_ACK;
}

static void twi_stop(void)
{
    TWCR = (1 << TWINT) | (1 << TWSTO) | (1 << TWEN);
}

/* 1 if the chip acknowledged the address, the register and every data byte */
static uint8_t pca_write(uint8_t reg, const uint8_t *data, uint8_t n)
{
    uint8_t ok = twi_start() && twi_write((uint8_t)(PCA_ADDR << 1)) && twi_write(reg);
    for (uint8_t i = 0; ok && i < n; i++)
        ok = twi_write(data[i]);
    twi_stop();
    return ok;
}

/* Prescaler (50 Hz) and wake-up; every channel is unknown until written again (the chip may have been reset). */
static uint8_t pca_setup(void)
{
    uint8_t b = 0x10; /* sleep, so that the prescaler can be written */
    uint8_t ok = pca_write(PCA_MODE1, &b, 1) && pca_write(PCA_PRESCALE, &prescale, 1);
    b = 0x20; /* wake, register auto-increment */
    ok = ok && pca_write(PCA_MODE1, &b, 1);
    for (uint8_t ch = 0; ch < HAL_N_SERVOS; ch++)
        last[ch] = 0xFFFF;
    ready = ok;
    return ok;
}

uint8_t hal_servo_init(void)
{
    TWSR = 0;
    TWBR = (uint8_t)((F_CPU / 400000UL - 16) / 2); /* 400 kHz */
    prescale = sl_pca9685_prescale(50);
    return pca_setup();
}

uint8_t hal_servo_write(const uint16_t *us, uint8_t n)
{
    if (!ready && !pca_setup()) /* after a failure: set the chip up again first */
        return 0;
    for (uint8_t ch = 0; ch < HAL_N_SERVOS; ch++) {
        uint16_t u = ch < n ? us[ch] : 0;
        if (u == last[ch])
            continue;
        uint8_t d[4] = {0, 0, 0, 0};
        if (u) {
            uint16_t off = sl_pca9685_off_count(u, prescale);
            d[2] = (uint8_t)off;
            d[3] = (uint8_t)(off >> 8);
        } else {
            d[3] = 0x10; /* full off */
        }
        if (!pca_write((uint8_t)(PCA_LED0 + 4 * ch), d, 4)) {
            ready = 0; /* retried from the prescaler on at the next call */
            return 0;
        }
        last[ch] = u;
    }
    return 1;
}
