/* servolink v1 device side: dispatch, ARM gating, limits, slew, link watchdog, OSC and GAIT modes.
 * Portable C99. Time and I/O are injected: feed bytes and ticks with a millisecond clock, read the
 * pulse widths to output from link->out_us. See firmware/PROTOCOL.md. */
#ifndef SL_LINK_H
#define SL_LINK_H

#include <stdint.h>

#include "gait.h"
#include "osc.h"
#include "proto.h"
#include "servo.h"

#ifndef SL_MAX_CH
#define SL_MAX_CH 8
#endif

#define SL_FW_MAJOR 1
#define SL_FW_MINOR 0
#define SL_FW_PATCH 0
#define SL_MAX_RATE_HZ 100
#define SL_PARK_DEFAULT_DPS 90 /* park speed when a channel has no slew limit */
#define SL_SLEW_PERIOD_MS 10
#define SL_GAIT_PIN_CELLS 6    /* at most: contact switches on A0..A5 */

/* link states */
#define SL_ST_DISARMED 0
#define SL_ST_ARMED 1
#define SL_ST_HOLD 2
#define SL_ST_PARK 3
#define SL_ST_RELEASED 4
/* modes */
#define SL_MODE_STREAM 0
#define SL_MODE_OSC 1
#define SL_MODE_GAIT 2
/* events */
#define SL_EV_HOLD 0xE1
#define SL_EV_PARK 0xE2
#define SL_EV_RELEASE 0xE3
#define SL_EV_SERVO_FAULT 0xE4 /* the servo back end failed a write (PCA9685: no answer on I2C) */
/* capability bits of HELLO_ACK */
#define SL_CAP_OSC 0x01
#define SL_CAP_GAIT 0x02
#define SL_CAP_PCA9685 0x04
#define SL_CAP_CONTACT_PINS 0x08
/* GAIT_SET flags */
#define SL_GAIT_CLOSED 0x01
#define SL_GAIT_PINS 0x02

typedef void (*sl_tx_fn)(void *user, const uint8_t *buf, uint8_t len);
/* fill air_mask (bit i = cell i in the air) from the contact inputs; n cells */
typedef void (*sl_contacts_fn)(void *user, uint8_t *air_mask, uint8_t n);

typedef struct {
    /* configuration */
    uint8_t n_ch;
    uint8_t caps;
    uint8_t pin_cells;           /* contact inputs of this board (0 = none), set by the board code */
    sl_chan_cfg_t cfg[SL_MAX_CH];
    uint16_t wd_ms, park_after_ms, release_after_ms;
    /* state */
    uint8_t state, mode;
    int16_t target[SL_MAX_CH], cur[SL_MAX_CH];
    uint16_t raw_us[SL_MAX_CH];  /* SET_PULSES override as requested (inside [min_us, max_us]), 0 = none */
    uint16_t out_us[SL_MAX_CH];  /* what the driver outputs now, 0 = no pulses: sl_link_output() of the state */
    uint8_t out_changed;
    /* memo of sl_link_output's pulse for (cur, raw_us) under the channel's current config: the 32-bit division is
     * slow on the AVR. A CONFIG_CH clears the channel's memo_ok bit; nothing else changes the config. */
    int16_t memo_cdeg[SL_MAX_CH];
    uint16_t memo_raw[SL_MAX_CH], memo_us[SL_MAX_CH];
    uint8_t memo_ok;
    sl_osc_t osc[SL_MAX_CH];
    uint8_t osc_on;              /* bit per channel */
    uint32_t osc_t0;
    uint8_t gait_n, gait_n1, gait_n2, gait_flags, gait_first;
    int16_t gait_inflate, gait_vent;
    uint8_t gait_air[8], gait_act[8];
    uint32_t last_rx_ms, trip_ms, last_slew_ms;
    /* statistics (PING) */
    uint16_t rx_ok, crc_err, framing_err, seq_gaps;
    uint8_t wdt_trips, last_seq, have_seq;
    uint8_t servo_faults, servo_fault_on; /* failed servo back-end writes (saturating), a fault is going on */
    /* I/O */
    sl_rx_t rx;
    sl_tx_fn tx;
    sl_contacts_fn contacts;
    void *user;
} sl_link_t;

/* Initialise (state DISARMED, default channel config) and send the boot HELLO_ACK (seq 0). */
void sl_link_init(sl_link_t *l, uint8_t n_ch, uint8_t extra_caps, sl_tx_fn tx, sl_contacts_fn contacts, void *user,
                  uint32_t now_ms);
void sl_link_feed(sl_link_t *l, uint8_t byte, uint32_t now_ms);
void sl_link_tick(sl_link_t *l, uint32_t now_ms);
/* The servo back end's result of its last write (1 = ok): a failure is counted (PING servo_faults) and the first
 * of a run reported with EVENT SERVO_FAULT; a success ends the run. */
void sl_link_servo_status(sl_link_t *l, uint8_t ok, uint32_t now_ms);

/* The pulse channel ch must output in the link's present state (0 = none), computed from scratch: pulses only
 * while ARMED / HOLD / PARK; a SET_PULSES override clamped to the channel's pulse window; otherwise the current
 * angle, clamped to the soft limits, mapped with trim and invert (PROTOCOL.md section 5). out_us always equals
 * this after every request and tick (the fuzz harness checks it). */
uint16_t sl_link_output(const sl_link_t *l, uint8_t ch);

#endif
