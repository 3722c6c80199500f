/* Interrupt-driven servo pulse sequencer (Timer1 normal mode, compare A interrupt).
 * Channels 0..7 on Arduino pins D4..D11 (PD4..PD7, PB0..PB3). D2/D3 (INT0/INT1) stay free: simavr polls
 * an external-interrupt pin driven as an output on every cycle. One channel is high at a
 * time; a 20 ms frame. Timer1 runs free at 2 MHz (prescaler 8, 0.5 us per tick); OCR1A is advanced
 * by each pulse width so that both edges of a pulse come from compare matches. */
#include <avr/interrupt.h>
#include <avr/io.h>
#include <util/atomic.h>

#include "hal.h"

#define FRAME_TICKS 40000u /* 20 ms */
#define IDLE_TICKS 100u    /* slot of a channel without pulses: 50 us */
#define LEAD_TICKS 40u     /* wake up 20 us before an edge */

const uint8_t hal_servo_caps = 0;
const uint8_t hal_contact_cells = 6;

static volatile uint16_t ticks[HAL_N_SERVOS];
static volatile int8_t cur = -1;
static volatile uint16_t frame_start;
static volatile uint16_t edge; /* timer value of the next edge */

/* bit of each channel in PORTD (channels 0..3) or PORTB (4..7) */
static const uint8_t pin_mask[HAL_N_SERVOS] = {1u << 4, 1u << 5, 1u << 6, 1u << 7, 1u << 0, 1u << 1, 1u << 2, 1u << 3};

/* The compare interrupt fires LEAD_TICKS before each edge, prepares the new port values, then spins on
 * TCNT1 until the edge's exact time and writes PORTD and PORTB back to back (the falling edge of one
 * channel and the rising edge of the next are one cycle apart). The UART and millisecond interrupts may
 * delay the entry by a few microseconds but not the edges, and every channel takes the same path, so a
 * pulse is exact to the timer's 0.5 us resolution. */
ISR(TIMER1_COMPA_vect)
{
    uint16_t at = edge;
    int8_t c = (int8_t)(cur + 1);
    uint8_t d = PORTD & (uint8_t)~0xF0u, b = PORTB & (uint8_t)~0x0Fu; /* every servo pin low ... */
    uint16_t next;
    if (c < HAL_N_SERVOS) {
        uint16_t t = ticks[c];
        if (t) { /* ... except the next channel's */
            if (c < 4)
                d |= pin_mask[c];
            else
                b |= pin_mask[c];
        } else {
            t = IDLE_TICKS;
        }
        next = (uint16_t)(at + t);
    } else {
        uint16_t elapsed = (uint16_t)(at - frame_start);
        next = (elapsed + IDLE_TICKS > FRAME_TICKS) ? (uint16_t)(at + IDLE_TICKS) : (uint16_t)(frame_start + FRAME_TICKS);
        frame_start = next;
        c = -1;
    }
    while ((int16_t)(TCNT1 - at) < 0)
        ;
    PORTD = d;
    PORTB = b;
    cur = c;
    edge = next;
    OCR1A = (uint16_t)(next - LEAD_TICKS);
}

uint8_t hal_servo_init(void)
{
    DDRD |= 0xF0; /* PD4..PD7 = D4..D7 */
    DDRB |= 0x0F; /* PB0..PB3 = D8..D11 */
    PORTD &= (uint8_t)~0xF0;
    PORTB &= (uint8_t)~0x0F;
    TCCR1A = 0;
    TCCR1B = (1 << CS11); /* normal mode, /8 */
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE)
    {
        frame_start = (uint16_t)(TCNT1 + 200);
        edge = frame_start;
        OCR1A = (uint16_t)(edge - LEAD_TICKS);
        cur = -1;
    }
    TIFR1 = (1 << OCF1A);
    TIMSK1 |= (1 << OCIE1A);
    return 1;
}

uint8_t hal_servo_write(const uint16_t *us, uint8_t n)
{
    for (uint8_t ch = 0; ch < HAL_N_SERVOS; ch++) {
        uint16_t t = ch < n ? (uint16_t)(us[ch] * 2u) : 0u;
        ATOMIC_BLOCK(ATOMIC_RESTORESTATE) { ticks[ch] = t; }
    }
    return 1;
}
