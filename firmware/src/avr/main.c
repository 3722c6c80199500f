/* servolink v1 firmware for the ATmega328P (Arduino Uno / Nano, 16 MHz).
 * UART0 115200 8N1 (U2X) with an interrupt-driven receive ring; Timer2 1 kHz millisecond tick;
 * the servo back end from hal.h; contact switches for GAIT mode on A0..A5 (cells 0..5; A0..A3 with the I2C
 * back end; closed to ground = on the ground, internal pull-up = in the air); the hardware watchdog (250 ms) catches firmware hangs.
 * Everything else is the portable core in ../core (compiled and unit-tested on the host too). */
#include <avr/interrupt.h>
#include <avr/io.h>
#include <avr/sleep.h>
#include <avr/wdt.h>
#include <util/atomic.h>

#include "../core/link.h"
#include "hal.h"

#ifndef BAUD_UBRR
#define BAUD_UBRR 16 /* 115200 with U2X at 16 MHz (+2.1 %) */
#endif

#define RX_RING 128u /* power of two, > one maximal frame (67 bytes) */

static volatile uint8_t rx_ring[RX_RING];
static volatile uint8_t rx_head, rx_tail;
static volatile uint32_t ms_now;
static sl_link_t link_state;

/* Keep the reset cause and stop the watchdog early (a WDT reset leaves it running). */
uint8_t mcusr_saved __attribute__((section(".noinit")));
void early_wdt_off(void) __attribute__((naked, used, section(".init3")));
void early_wdt_off(void)
{
    mcusr_saved = MCUSR;
    MCUSR = 0;
    wdt_disable();
}

ISR(USART_RX_vect)
{
    uint8_t b = UDR0;
    uint8_t h = rx_head;
    uint8_t n = (uint8_t)((h + 1u) & (RX_RING - 1u));
    if (n != rx_tail) { /* drop on overflow: the frame CRC will catch it */
        rx_ring[h] = b;
        rx_head = n;
    }
}

ISR(TIMER2_COMPA_vect)
{
    ms_now++;
}

static uint32_t millis(void)
{
    uint32_t t;
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE) { t = ms_now; }
    return t;
}

static void uart_tx(void *user, const uint8_t *buf, uint8_t len)
{
    (void)user;
    for (uint8_t i = 0; i < len; i++) {
        while (!(UCSR0A & (1 << UDRE0)))
            ;
        UDR0 = buf[i];
    }
}

static void read_contacts(void *user, uint8_t *air_mask, uint8_t n)
{
    (void)user;
    /* cell k on A0 + k (PC0..PC5); 1 = open switch = in the air. (Port C only: the servo interrupt rewrites
     * PORTD and PORTB, which an emulator may take for a change of those ports' input pins.) */
    uint8_t pins = PINC & 0x3F;
    if (n > hal_contact_cells)
        n = hal_contact_cells;
    air_mask[0] = (uint8_t)(pins & (uint8_t)((1u << n) - 1u));
}

int main(void)
{
    /* UART0 */
    UCSR0A = (1 << U2X0); /* before UBRR: simavr derives the baud rate when UBRR is written */
    UBRR0H = (uint8_t)(BAUD_UBRR >> 8);
    UBRR0L = (uint8_t)BAUD_UBRR;
    UCSR0B = (1 << RXEN0) | (1 << TXEN0) | (1 << RXCIE0);
    UCSR0C = (1 << UCSZ01) | (1 << UCSZ00);
    /* Timer2: CTC, /64, 250 counts = 1 ms */
    TCCR2A = (1 << WGM21);
    TCCR2B = (1 << CS22);
    OCR2A = 249;
    TIMSK2 = (1 << OCIE2A);
    /* contact inputs with pull-ups */
    uint8_t cmask = (uint8_t)((1u << hal_contact_cells) - 1u);
    DDRC &= (uint8_t)~cmask;
    PORTC |= cmask;

    uint8_t servo_ok = hal_servo_init();
    uint32_t servo_retry_ms = 0;
    set_sleep_mode(SLEEP_MODE_IDLE);
    sei();
    wdt_enable(WDTO_250MS);
    sl_link_init(&link_state, HAL_N_SERVOS, (uint8_t)(hal_servo_caps | SL_CAP_CONTACT_PINS), uart_tx, read_contacts,
                 0, millis());
    link_state.pin_cells = hal_contact_cells;
    sl_link_servo_status(&link_state, servo_ok, millis());

    for (;;) {
        wdt_reset();
        while (rx_tail != rx_head) {
            uint8_t t = rx_tail;
            uint8_t b = rx_ring[t];
            rx_tail = (uint8_t)((t + 1u) & (RX_RING - 1u));
            sl_link_feed(&link_state, b, millis());
        }
        sl_link_tick(&link_state, millis());
        /* a failed back-end write (PCA9685 absent, bus fault) is retried every 20 ms and reported to the host */
        if (link_state.out_changed && (servo_ok || (uint32_t)(millis() - servo_retry_ms) >= 20)) {
            link_state.out_changed = 0;
            servo_ok = hal_servo_write(link_state.out_us, link_state.n_ch);
            if (!servo_ok) {
                link_state.out_changed = 1;
                servo_retry_ms = millis();
            }
            sl_link_servo_status(&link_state, servo_ok, millis());
        }
        /* idle until the next interrupt (UART byte, 1 ms tick, servo edge); checked with interrupts off so
         * that a byte arriving now is not slept over */
        cli();
        if (rx_tail == rx_head) {
            sleep_enable();
            sei();
            sleep_cpu();
            sleep_disable();
        }
        sei();
    }
}
