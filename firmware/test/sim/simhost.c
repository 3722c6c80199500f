/* simhost: run the servolink firmware in simavr with UART0 bridged to a pseudo-terminal.
 *
 * A TEST TOOL ONLY (it links libsimavr, GPL-3; it is never shipped with the workbench).
 *   simhost [--realtime] [--pulse-log FILE] [--link PATH] [--seconds S] [--mcu NAME] [--freq HZ] FIRMWARE.elf
 * Prints "PTY /dev/pts/N" on stdout once the pty is ready; pyserial opens it like a real board.
 * --pulse-log writes "<sim_seconds> <channel> <width_us>" whenever a servo pin's pulse width changes by more
 * than 0.3 us, and "<sim_seconds> <channel> off" when a pin stops pulsing (no rising edge for 60 ms).
 * Channels 0..7 are Arduino D4..D11 (PD4..PD7, PB0..PB3), the pins of the firmware's ISR servo driver.
 * --realtime paces simulated time to the wall clock (needed for any timing-related test).
 * --pca9685 attaches an emulated PCA9685 at I2C address 0x40 instead of watching the pins (the firmware's
 * BACKEND=pca9685 build); its channels are logged the same way.
 * --contacts FILE drives the GAIT-mode contact switch inputs from a file ("00011111": cell 0 first). */
#define _GNU_SOURCE
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <poll.h>
#include <pty.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <termios.h>
#include <time.h>
#include <unistd.h>

#include "avr_ioport.h"
#include "avr_twi.h"
#include "avr_uart.h"
#include "sim_avr.h"
#include "sim_elf.h"
#include "sim_irq.h"

#define N_CH 8

static avr_t *avr;
static int pty_master = -1;
static int uart_xoff;
static FILE *pulse_log;
static int realtime;
static struct timespec wall0;
static avr_cycle_count_t rise[N_CH];
static avr_cycle_count_t last_rise[N_CH];
static double last_width[N_CH];
static int pin_on[N_CH];
/* --pca9685: a PCA9685 PWM driver at I2C address 0x40, answering the firmware's TWI master. Its register
 * file is kept here; after each write transaction every LEDn channel is reported in the pulse log like a
 * pin: width = OFF count * (PRESCALE + 1) / 25 MHz (ON must be 0), "off" for the full-off bit. */
static int pca_enabled;
static uint8_t pca_reg[256];
static uint8_t pca_ptr, pca_selected, pca_first_byte;

static double pca_last[N_CH];
static int pca_logged[N_CH];

/* --contacts FILE: the contact switches of GAIT mode. The file holds one character per cell, '1' = in the
 * air (switch open), '0' = on the ground (switch closed to GND); it is re-read every 10 ms of simulated time
 * and drives the input pins: cell k = A0 + k (PC0..PC5). */
static const char *contacts_path;
static char contacts_last[16];

static void contacts_poll(void)
{
    char buf[16] = {0};
    FILE *f = fopen(contacts_path, "r");
    if (!f)
        return;
    size_t n = fread(buf, 1, sizeof buf - 1, f);
    fclose(f);
    buf[n] = 0;
    if (!strcmp(buf, contacts_last))
        return;
    strcpy(contacts_last, buf);
    for (int cell = 0; cell < 6 && buf[cell] && buf[cell] != '\n'; cell++)
        avr_raise_irq(avr_io_getirq(avr, AVR_IOCTL_IOPORT_GETIRQ('C'), IOPORT_IRQ_PIN0 + cell), buf[cell] == '1');
}

static uint8_t inbuf[4096];
static size_t in_len, in_pos;
static volatile sig_atomic_t stop_requested;

static void on_signal(int sig)
{
    (void)sig;
    stop_requested = 1;
}

/* The AVR sleeps between interrupts; simavr then skips to the next event. Its default "raw" sleep callback
 * would also usleep() for that long; pacing is done here instead (--realtime), so do nothing. */
static void no_sleep(avr_t *a, avr_cycle_count_t how_long)
{
    (void)a;
    (void)how_long;
}

static double sim_seconds(void) { return (double)avr->cycle / (double)avr->frequency; }

static double wall_seconds(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)(t.tv_sec - wall0.tv_sec) + 1e-9 * (double)(t.tv_nsec - wall0.tv_nsec);
}

static void uart_out_hook(struct avr_irq_t *irq, uint32_t value, void *param)
{
    (void)irq;
    (void)param;
    uint8_t b = (uint8_t)value;
    for (int tries = 0; tries < 1000; tries++) {
        ssize_t n = write(pty_master, &b, 1);
        if (n == 1 || (n < 0 && errno != EAGAIN && errno != EINTR))
            return;
        usleep(100);
    }
}

static void xon_hook(struct avr_irq_t *irq, uint32_t value, void *param)
{
    (void)irq;
    (void)value;
    (void)param;
    uart_xoff = 0;
}

static void xoff_hook(struct avr_irq_t *irq, uint32_t value, void *param)
{
    (void)irq;
    (void)value;
    (void)param;
    uart_xoff = 1;
}

static void pin_hook(struct avr_irq_t *irq, uint32_t value, void *param)
{
    (void)irq;
    int ch = (int)(intptr_t)param;
    if (value) {
        rise[ch] = avr->cycle;
        last_rise[ch] = avr->cycle;
        return;
    }
    if (!rise[ch])
        return;
    double w = (double)(avr->cycle - rise[ch]) * 1e6 / (double)avr->frequency;
    rise[ch] = 0;
    if (!pin_on[ch] || fabs(w - last_width[ch]) > 0.3) {
        pin_on[ch] = 1;
        last_width[ch] = w;
        if (pulse_log) {
            fprintf(pulse_log, "%.6f %d %.2f\n", sim_seconds(), ch, w);
            fflush(pulse_log);
        }
    }
}

static void pca_report(void)
{
    for (int ch = 0; ch < N_CH; ch++) {
        const uint8_t *r = &pca_reg[0x06 + 4 * ch];
        int on = r[0] | ((r[1] & 0x0F) << 8), off = r[2] | ((r[3] & 0x0F) << 8);
        int full_off = r[3] & 0x10, sleeping = pca_reg[0] & 0x10;
        double w = (full_off || sleeping) ? -1.0 : (double)(off - on) * (pca_reg[0xFE] + 1) / 25.0;
        if (pca_logged[ch] && fabs(w - pca_last[ch]) < 0.01)
            continue;
        if (!pca_logged[ch] && w < 0)
            continue;
        pca_logged[ch] = 1;
        pca_last[ch] = w;
        if (pulse_log) {
            if (w < 0)
                fprintf(pulse_log, "%.6f %d off\n", sim_seconds(), ch);
            else
                fprintf(pulse_log, "%.6f %d %.2f\n", sim_seconds(), ch, w);
            fflush(pulse_log);
        }
    }
}

static void twi_hook(struct avr_irq_t *irq, uint32_t value, void *param)
{
    (void)irq;
    (void)param;
    avr_twi_msg_irq_t v;
    v.u.v = value;
    avr_irq_t *in = avr_io_getirq(avr, AVR_IOCTL_TWI_GETIRQ(0), TWI_IRQ_INPUT);
    if (v.u.twi.msg & TWI_COND_STOP) {
        if (pca_selected)
            pca_report();
        pca_selected = 0;
    }
    if (v.u.twi.msg & TWI_COND_START) {
        pca_selected = 0;
        if ((v.u.twi.addr >> 1) == 0x40 && !(v.u.twi.addr & 1)) { /* our address, write */
            pca_selected = v.u.twi.addr;
            pca_first_byte = 1;
            avr_raise_irq(in, avr_twi_irq_msg(TWI_COND_ACK, pca_selected, 1));
        }
    }
    if (pca_selected && (v.u.twi.msg & TWI_COND_WRITE)) {
        avr_raise_irq(in, avr_twi_irq_msg(TWI_COND_ACK, pca_selected, 1));
        if (pca_first_byte) {
            pca_ptr = v.u.twi.data;
            pca_first_byte = 0;
        } else {
            /* PRESCALE is writable only while the oscillator sleeps (datasheet) */
            if (pca_ptr != 0xFE || (pca_reg[0] & 0x10))
                pca_reg[pca_ptr] = v.u.twi.data;
            if (pca_reg[0] & 0x20) /* auto-increment */
                pca_ptr++;
        }
    }
}

/* every 100 us of simulated time: feed the UART from the pty, pace to the wall clock, check for
 * pins that stopped pulsing */
static avr_cycle_count_t poll_timer(struct avr_t *a, avr_cycle_count_t when, void *param)
{
    (void)param;
    if (in_pos >= in_len) {
        ssize_t n = read(pty_master, inbuf, sizeof inbuf);
        in_len = n > 0 ? (size_t)n : 0;
        in_pos = 0;
    }
    /* one byte per poll at most 100 us apart is faster than 115200 baud (87 us/byte) would allow
     * anyway; the UART's fifo flow control (XOFF) is respected */
    for (int k = 0; k < 2 && in_pos < in_len && !uart_xoff; k++)
        avr_raise_irq(avr_io_getirq(a, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_INPUT), inbuf[in_pos++]);
    static unsigned polls;
    if (contacts_path && ++polls % 100 == 0)
        contacts_poll();
    avr_cycle_count_t gap = (avr_cycle_count_t)(0.060 * (double)a->frequency);
    for (int ch = 0; ch < N_CH; ch++) {
        if (pin_on[ch] && a->cycle - last_rise[ch] > gap) {
            pin_on[ch] = 0;
            if (pulse_log) {
                fprintf(pulse_log, "%.6f %d off\n", sim_seconds(), ch);
                fflush(pulse_log);
            }
        }
    }
    if (realtime) {
        /* wait until the wall clock catches up, but wake at once when the host writes (lower latency) */
        double ahead = sim_seconds() - wall_seconds();
        if (ahead > 0.0005 && in_pos >= in_len) {
            struct pollfd pfd = {pty_master, POLLIN, 0};
            int ms = (int)(ahead * 1000.0);
            poll(&pfd, 1, ms > 0 ? ms : 1);
        } else if (ahead > 0.0005) {
            usleep((useconds_t)(ahead * 1e6));
        }
    }
    return when + a->frequency / 10000;
}

static void usage(void)
{
    fprintf(stderr, "usage: simhost [--realtime] [--pca9685] [--contacts FILE] [--pulse-log FILE] [--link PATH] [--seconds S] [--mcu NAME] "
                    "[--freq HZ] FIRMWARE.elf\n");
    exit(2);
}

int main(int argc, char **argv)
{
    const char *elf = NULL, *link_path = NULL, *log_path = NULL, *mcu = "atmega328p";
    double seconds = 0;
    unsigned long freq = 16000000UL;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--realtime"))
            realtime = 1;
        else if (!strcmp(argv[i], "--pca9685"))
            pca_enabled = 1;
        else if (!strcmp(argv[i], "--contacts") && i + 1 < argc)
            contacts_path = argv[++i];
        else if (!strcmp(argv[i], "--pulse-log") && i + 1 < argc)
            log_path = argv[++i];
        else if (!strcmp(argv[i], "--link") && i + 1 < argc)
            link_path = argv[++i];
        else if (!strcmp(argv[i], "--seconds") && i + 1 < argc)
            seconds = atof(argv[++i]);
        else if (!strcmp(argv[i], "--mcu") && i + 1 < argc)
            mcu = argv[++i];
        else if (!strcmp(argv[i], "--freq") && i + 1 < argc)
            freq = strtoul(argv[++i], NULL, 10);
        else if (argv[i][0] == '-')
            usage();
        else
            elf = argv[i];
    }
    if (!elf)
        usage();

    elf_firmware_t fw;
    memset(&fw, 0, sizeof fw);
    if (elf_read_firmware(elf, &fw) != 0) {
        fprintf(stderr, "simhost: cannot read %s\n", elf);
        return 1;
    }
    avr = avr_make_mcu_by_name(mcu);
    if (!avr) {
        fprintf(stderr, "simhost: unknown mcu %s\n", mcu);
        return 1;
    }
    avr_init(avr);
    fw.frequency = (uint32_t)freq;
    strncpy(fw.mmcu, mcu, sizeof fw.mmcu - 1);
    avr_load_firmware(avr, &fw);
    avr->frequency = (uint32_t)freq;
    avr->log = 1;
    avr->sleep = no_sleep;

    if (log_path) {
        pulse_log = fopen(log_path, "w");
        if (!pulse_log) {
            perror(log_path);
            return 1;
        }
    }

    int slave;
    char name[256];
    if (openpty(&pty_master, &slave, name, NULL, NULL) < 0) {
        perror("openpty");
        return 1;
    }
    struct termios tio;
    tcgetattr(slave, &tio);
    cfmakeraw(&tio);
    tcsetattr(slave, TCSANOW, &tio);
    tcgetattr(pty_master, &tio);
    cfmakeraw(&tio);
    tcsetattr(pty_master, TCSANOW, &tio);
    fcntl(pty_master, F_SETFL, fcntl(pty_master, F_GETFL) | O_NONBLOCK);
    /* the slave stays open here, so the master never reads EIO while no client has it open */
    if (link_path) {
        unlink(link_path);
        if (symlink(name, link_path) < 0)
            perror("symlink");
    }

    uint32_t flags = 0;
    avr_ioctl(avr, AVR_IOCTL_UART_GET_FLAGS('0'), &flags);
    /* no console printing; no usleep() when the firmware polls UCSR0A (its transmitter waits on UDRE) */
    flags &= ~(uint32_t)(AVR_UART_FLAG_STDIO | AVR_UART_FLAG_POLL_SLEEP);
    avr_ioctl(avr, AVR_IOCTL_UART_SET_FLAGS('0'), &flags);
    avr_irq_register_notify(avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_OUTPUT), uart_out_hook, NULL);
    avr_irq_register_notify(avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_OUT_XON), xon_hook, NULL);
    avr_irq_register_notify(avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_OUT_XOFF), xoff_hook, NULL);
    if (pca_enabled) {
        pca_reg[0] = 0x11; /* power-on MODE1: sleep, all-call */
        pca_reg[0xFE] = 0x1E;
        for (int ch = 0; ch < 16; ch++)
            pca_reg[0x06 + 4 * ch + 3] = 0x10; /* full off */
        avr_irq_register_notify(avr_io_getirq(avr, AVR_IOCTL_TWI_GETIRQ(0), TWI_IRQ_OUTPUT), twi_hook, NULL);
    }
    for (int ch = 0; ch < N_CH && !pca_enabled; ch++) {
        char port = ch < 4 ? 'D' : 'B';
        int pin = ch < 4 ? ch + 4 : ch - 4;
        avr_irq_register_notify(avr_io_getirq(avr, AVR_IOCTL_IOPORT_GETIRQ(port), IOPORT_IRQ_PIN0 + pin), pin_hook,
                                (void *)(intptr_t)ch);
    }
    avr_cycle_timer_register(avr, avr->frequency / 10000, poll_timer, NULL);

    printf("PTY %s\n", name);
    fflush(stdout);
    clock_gettime(CLOCK_MONOTONIC, &wall0);

    signal(SIGTERM, on_signal);
    signal(SIGINT, on_signal);
    avr_cycle_count_t stop = seconds > 0 ? (avr_cycle_count_t)(seconds * (double)avr->frequency) : 0;
    for (;;) {
        int st = avr_run(avr);
        if (st == cpu_Done || st == cpu_Crashed) {
            fprintf(stderr, "simhost: firmware stopped (state %d) at %.3f s\n", st, sim_seconds());
            break;
        }
        if ((stop && avr->cycle >= stop) || stop_requested)
            break;
    }
    double wall = wall_seconds();
    fprintf(stderr, "simhost: %.3f s simulated in %.3f s wall (%.2fx real time)\n", sim_seconds(), wall,
            wall > 0 ? sim_seconds() / wall : 0.0);
    if (link_path)
        unlink(link_path);
    return 0;
}
