/* Invariant fuzz target for the firmware core (parser, dispatcher, limits, watchdog, OSC, GAIT).
 * libFuzzer entry point LLVMFuzzerTestOneInput (clang -fsanitize=fuzzer,address,undefined); with
 * -DSL_FUZZ_STANDALONE a small driver mutates the seed files with a fixed-seed PRNG for a bounded time.
 *
 * The input is a byte stream for the link with escapes:
 *   0xFE k            advance the clock by k * 8 ms and tick (watchdog, slew, generators);
 *   0xFD n t p[n-1]   a *valid* frame of type t with payload p, built here with its COBS and CRC, so that the
 *                     fuzzer reaches the dispatcher without forging CRCs;
 *   0xFC s            the next 0xFD frame carries seq s (sequence gaps, seq 0 / 0xFF);
 * every other byte goes to the link as it is (framing, COBS and CRC errors).
 *
 * Checked after every byte and every tick, beyond the sanitizers' memory and UB checks (PROTOCOL.md):
 *   limits   every pulse is 0 or inside the channel's pulse window: [min_us, max_us] and the widths of the soft
 *            limits lo..hi; the angle lies in [lo, hi]; out_us equals a reference written here from section 5
 *            (not the firmware's code) for the state, the config, the angle and the override;
 *   pulses   none unless ARMED / HOLD / PARK, always some then (section 6: RELEASE and DISARM stop them);
 *   HOLD     a tick ending in HOLD changes no output; HOLD lasts park_after_ms, PARK release_after_ms more;
 *   PARK     every tick moves each angle towards its park angle, by at most the slew step (90 deg/s if none);
 *   ARM      the link becomes ARMED only by an ACKed ARM; motion ACKs carry state ARMED; the watchdog trips
 *            exactly when the host is silent for longer than watchdog_ms; events come HOLD, PARK, RELEASE;
 *   counters rx_ok, crc_err, framing_err and seq_gaps equal a shadow decoder's counts of the same bytes;
 *            wdt_trips equals the HOLD events; every frame gets exactly one reply with its seq, every
 *            undecodable one a NAK with seq 0xFF; a PING's counters are those of its moment;
 *   replies  every byte the device sends decodes as a valid frame; outputs change only with an ACK or a tick. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "link.h"

typedef struct {
    sl_rx_t rx;
    int replies, acks, events, holds, armed_acks;
    uint8_t last_event, last_reply_seq, last_reply_type;
    const sl_link_t *l;
    uint16_t want_rx_ok, want_crc, want_framing, want_gaps; /* for PING replies */
    uint8_t booting;
} sink_t;

static void fz_abort(const char *why)
{
    fprintf(stderr, "fuzz invariant violated: %s\n", why);
    abort();
}

static void sink_tx(void *user, const uint8_t *buf, uint8_t len)
{
    sink_t *s = (sink_t *)user;
    if (len < 5 || buf[len - 1] != 0)
        fz_abort("reply frame shape");
    for (uint8_t i = 0; i < len; i++) {
        sl_packet_t p;
        uint8_t err = 0;
        uint8_t r = sl_rx_feed(&s->rx, buf[i], &p, &err);
        if (r == SL_RX_ERR)
            fz_abort("device sent an undecodable frame");
        if (r != SL_RX_OK)
            continue;
        if (p.type == SL_T_EVENT) {
            uint8_t code = p.payload[0];
            if (p.seq != 0 || p.plen != 6)
                fz_abort("EVENT shape");
            if ((code == SL_EV_PARK && s->last_event != SL_EV_HOLD) ||
                (code == SL_EV_RELEASE && s->last_event != SL_EV_PARK) ||
                (code == SL_EV_HOLD && s->l->state != SL_ST_HOLD))
                fz_abort("watchdog events out of order");
            s->last_event = code;
            s->events++;
            if (code == SL_EV_HOLD)
                s->holds++;
            continue;
        }
        if (p.type == SL_T_HELLO_ACK && s->booting)
            continue; /* the boot banner */
        s->replies++;
        s->last_reply_seq = p.seq;
        s->last_reply_type = p.type;
        if (p.type == SL_T_NAK && p.payload[0] <= SL_E_TOO_LONG && p.seq != SL_SEQ_NONE)
            fz_abort("framing NAK without seq 0xFF");
        if (p.type == SL_T_ACK) {
            s->acks++;
            uint8_t rq = p.payload[0], st = p.payload[1];
            if (st != s->l->state)
                fz_abort("ACK reports another state than the link's");
            if ((rq == SL_T_SET_ANGLES || rq == SL_T_SET_PULSES) && (st != SL_ST_ARMED || s->l->mode != SL_MODE_STREAM))
                fz_abort("motion accepted while not ARMED in STREAM mode");
            if (rq == SL_T_ARM)
                s->armed_acks++;
            if (rq == SL_T_PING &&
                (sl_get_u16(p.payload + 6) != s->want_rx_ok || sl_get_u16(p.payload + 8) != s->want_crc ||
                 sl_get_u16(p.payload + 10) != s->want_framing || sl_get_u16(p.payload + 12) != s->want_gaps))
                fz_abort("PING counters differ from the frames received");
        }
    }
}

/* PROTOCOL.md section 5, written again here: us = floor(((min+max) 9000 + a (max-min) + 9000) / 18000), clamped */
static int32_t ref_us(const sl_chan_cfg_t *c, int32_t cdeg)
{
    if (cdeg < c->lo_cdeg)
        cdeg = c->lo_cdeg;
    if (cdeg > c->hi_cdeg)
        cdeg = c->hi_cdeg;
    int32_t a = (c->invert ? -cdeg : cdeg) + c->trim_cdeg;
    int64_t num = ((int64_t)c->min_us + c->max_us) * 9000 + (int64_t)a * (c->max_us - c->min_us) + 9000;
    int64_t us = num >= 0 ? num / 18000 : -((-num + 17999) / 18000);
    if (us < c->min_us)
        us = c->min_us;
    if (us > c->max_us)
        us = c->max_us;
    return (int32_t)us;
}

static int on(const sl_link_t *l)
{
    return l->state == SL_ST_ARMED || l->state == SL_ST_HOLD || l->state == SL_ST_PARK;
}

static void check_outputs(const sl_link_t *l)
{
    for (uint8_t ch = 0; ch < l->n_ch; ch++) {
        const sl_chan_cfg_t *c = &l->cfg[ch];
        uint16_t us = l->out_us[ch];
        if (sl_chan_cfg_check(c))
            fz_abort("invalid channel config accepted");
        if (!on(l) && us)
            fz_abort("pulses while disarmed/released");
        if (on(l) && !us)
            fz_abort("no pulses while ARMED/HOLD/PARK");
        if (l->cur[ch] < c->lo_cdeg || l->cur[ch] > c->hi_cdeg)
            fz_abort("angle outside the soft limits");
        if (!us)
            continue;
        int32_t w0 = ref_us(c, c->lo_cdeg), w1 = ref_us(c, c->hi_cdeg);
        int32_t lo = w0 < w1 ? w0 : w1, hi = w0 < w1 ? w1 : w0;
        if (us < c->min_us || us > c->max_us)
            fz_abort("pulse outside [min_us, max_us]");
        if (us < lo || us > hi)
            fz_abort("pulse outside the soft limits' pulse window");
        int32_t want = l->raw_us[ch] ? (l->raw_us[ch] < lo ? lo : l->raw_us[ch] > hi ? hi : l->raw_us[ch])
                                     : ref_us(c, l->cur[ch]);
        if (us != want)
            fz_abort("pulse differs from the reference mapping of state, config, angle and override (stale value)");
    }
}

typedef struct {
    sl_rx_t rx;
    uint16_t ok, crc, framing, gaps;
    uint8_t last_seq, have_seq;
} shadow_t;

static int shadow_feed(shadow_t *sh, uint8_t b)
{
    sl_packet_t p;
    uint8_t err = 0;
    uint8_t r = sl_rx_feed(&sh->rx, b, &p, &err);
    if (r == SL_RX_OK) {
        sh->ok++;
        uint8_t next = (uint8_t)(sh->last_seq >= 254 ? 1 : sh->last_seq + 1);
        if (sh->have_seq && p.seq != next)
            sh->gaps++;
        sh->last_seq = p.seq;
        sh->have_seq = 1;
        return 1;
    }
    if (r == SL_RX_ERR) {
        if (err == SL_E_CRC)
            sh->crc++;
        else
            sh->framing++;
        return 2;
    }
    return 0;
}

static void tick(sl_link_t *l, sink_t *s, uint32_t now)
{
    uint16_t before[SL_MAX_CH];
    int16_t cur0[SL_MAX_CH];
    memcpy(before, l->out_us, sizeof before);
    memcpy(cur0, l->cur, sizeof cur0);
    uint8_t st0 = l->state;
    int armed_acks = s->armed_acks;
    uint32_t silent = now - l->last_rx_ms;
    sl_link_tick(l, now);
    if (s->armed_acks != armed_acks || (st0 != SL_ST_ARMED && l->state == SL_ST_ARMED))
        fz_abort("ARMED without an ARM request");
    if (st0 == SL_ST_ARMED && silent > l->wd_ms && l->state == SL_ST_ARMED)
        fz_abort("watchdog did not trip");
    if (st0 == SL_ST_ARMED && silent <= l->wd_ms && l->state != SL_ST_ARMED)
        fz_abort("watchdog tripped early");
    if (l->state == SL_ST_HOLD && (now - l->trip_ms >= l->park_after_ms || memcmp(before, l->out_us, sizeof before)))
        fz_abort("HOLD did not keep the last pulses for park_after_ms");
    if (l->state == SL_ST_PARK && now - l->trip_ms >= (uint32_t)l->park_after_ms + l->release_after_ms)
        fz_abort("PARK did not release after release_after_ms");
    if (l->state != st0 && (l->state == SL_ST_HOLD || l->state == SL_ST_PARK || l->state == SL_ST_RELEASED) &&
        s->last_event != (l->state == SL_ST_HOLD ? SL_EV_HOLD : l->state == SL_ST_PARK ? SL_EV_PARK : SL_EV_RELEASE))
        fz_abort("watchdog state change without its EVENT");
    if (l->wdt_trips != (s->holds > 255 ? 255 : s->holds))
        fz_abort("wdt_trips differs from the HOLD events");
    if (st0 == SL_ST_PARK && l->state == SL_ST_PARK) {
        for (uint8_t ch = 0; ch < l->n_ch; ch++) {
            int32_t park = l->cfg[ch].park_cdeg, d0 = cur0[ch] - park, d1 = l->cur[ch] - park;
            int32_t rate = l->cfg[ch].max_slew_dps ? l->cfg[ch].max_slew_dps : SL_PARK_DEFAULT_DPS;
            int32_t step = l->cur[ch] - cur0[ch];
            if ((d0 >= 0 ? d1 > d0 || d1 < 0 : d1 < d0 || d1 > 0) || step > rate * 10 || step < -rate * 10)
                fz_abort("PARK does not ramp towards the park angle at the slew limit");
        }
    }
    check_outputs(l);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static sl_link_t l;
    sink_t s;
    shadow_t sh;
    memset(&s, 0, sizeof s);
    memset(&sh, 0, sizeof sh);
    sl_rx_init(&s.rx);
    sl_rx_init(&sh.rx);
    s.l = &l;
    uint32_t now = 0;
    s.booting = 1;
    sl_link_init(&l, SL_MAX_CH, 0, sink_tx, NULL, &s, now);
    s.booting = 0;
    check_outputs(&l);
    uint8_t seq = 1;
    int seq_forced = -1;
    for (size_t i = 0; i < size; i++) {
        if (data[i] == 0xFE && i + 1 < size) {
            now += (uint32_t)data[++i] * 8u;
            tick(&l, &s, now);
            continue;
        }
        if (data[i] == 0xFC && i + 1 < size) {
            seq_forced = data[++i];
            continue;
        }
        uint8_t frame[SL_MAX_ENCODED + 1];
        const uint8_t *bytes = &data[i];
        uint8_t nbytes = 1;
        if (data[i] == 0xFD && i + 2 < size) {
            uint8_t n = data[i + 1];
            if (n < 1)
                n = 1;
            if (n > SL_MAX_PAYLOAD + 1)
                n = SL_MAX_PAYLOAD + 1;
            if (i + 2 + n > size)
                n = (uint8_t)(size - i - 2);
            uint8_t q = seq_forced >= 0 ? (uint8_t)seq_forced : seq;
            nbytes = sl_build_frame(data[i + 2], q, &data[i + 3], (uint8_t)(n - 1), frame);
            seq = (uint8_t)(q >= 254 ? 1 : q + 1);
            seq_forced = -1;
            bytes = frame;
            i += 1 + n;
        }
        for (uint8_t k = 0; k < nbytes; k++) {
            uint16_t before[SL_MAX_CH];
            memcpy(before, l.out_us, sizeof before);
            uint8_t st0 = l.state;
            int acks = s.acks, replies = s.replies, armed_acks = s.armed_acks;
            /* the shadow decoder sees the byte first: a PING reply reports the counts including itself */
            int kind = shadow_feed(&sh, bytes[k]);
            s.want_rx_ok = sh.ok;
            s.want_crc = sh.crc;
            s.want_framing = sh.framing;
            s.want_gaps = sh.gaps;
            sl_link_feed(&l, bytes[k], now);
            if (s.acks == acks && memcmp(before, l.out_us, sizeof before))
                fz_abort("outputs changed without an ACK");
            if (st0 != SL_ST_ARMED && l.state == SL_ST_ARMED && s.armed_acks == armed_acks)
                fz_abort("ARMED without an ARM request");
            if (s.replies != replies + (kind != 0))
                fz_abort("a frame did not get exactly one reply");
            if (kind == 2 && s.last_reply_seq != SL_SEQ_NONE)
                fz_abort("an undecodable frame got a reply without seq 0xFF");
            if (l.rx_ok != sh.ok || l.crc_err != sh.crc || l.framing_err != sh.framing || l.seq_gaps != sh.gaps)
                fz_abort("link counters differ from the frames received");
            if (kind) /* between delimiters nothing but the memcmp above can change */
                check_outputs(&l);
        }
    }
    return 0;
}

#ifdef SL_FUZZ_STANDALONE
#include <dirent.h>
#include <time.h>

static uint32_t rng = 0x12345678u;
static uint32_t xr(void)
{
    rng ^= rng << 13;
    rng ^= rng >> 17;
    rng ^= rng << 5;
    return rng;
}

int main(int argc, char **argv)
{
    double seconds = 1e9;
    unsigned long max_runs = 0;
    const char *dir = NULL;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--seconds") && i + 1 < argc)
            seconds = atof(argv[++i]);
        else if (!strcmp(argv[i], "--runs") && i + 1 < argc)
            max_runs = strtoul(argv[++i], NULL, 10);
        else
            dir = argv[i];
    }
    if (seconds >= 1e9 && !max_runs)
        seconds = 10;
    static uint8_t seeds[64][512];
    FILE *one = dir ? fopen(dir, "rb") : NULL;
    DIR *isdir = dir ? opendir(dir) : NULL;
    if (one && !isdir) { /* a single input file: run it once (the regressions) */
        size_t m = fread(seeds[0], 1, sizeof seeds[0], one);
        fclose(one);
        LLVMFuzzerTestOneInput(seeds[0], m);
        printf("fuzz_link: ran %s\n", dir);
        return 0;
    }
    if (one)
        fclose(one);
    if (isdir)
        closedir(isdir);
    size_t seed_len[64];
    int nseeds = 0;
    if (dir) {
        DIR *d = opendir(dir);
        struct dirent *e;
        while (d && (e = readdir(d)) && nseeds < 64) {
            if (e->d_name[0] == '.')
                continue;
            char path[1024];
            snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
            FILE *f = fopen(path, "rb");
            if (!f)
                continue;
            seed_len[nseeds] = fread(seeds[nseeds], 1, sizeof seeds[0], f);
            fclose(f);
            nseeds++;
        }
        if (d)
            closedir(d);
    }
    if (!nseeds) {
        seed_len[0] = 1;
        seeds[0][0] = 0;
        nseeds = 1;
    }
    clock_t end = clock() + (clock_t)(seconds * CLOCKS_PER_SEC);
    unsigned long runs = 0;
    uint8_t buf[1024];
    while (clock() < end && (!max_runs || runs < max_runs)) {
        for (int k = 0; k < 256; k++, runs++) {
            /* splice one or two seeds, then mutate a few bytes */
            size_t n = 0;
            int parts = 1 + (int)(xr() % 3);
            for (int pidx = 0; pidx < parts; pidx++) {
                int sidx = (int)(xr() % (uint32_t)nseeds);
                size_t m = seed_len[sidx];
                if (n + m > sizeof buf)
                    break;
                memcpy(buf + n, seeds[sidx], m);
                n += m;
            }
            int muts = (int)(xr() % 8);
            for (int mu = 0; mu < muts && n; mu++) {
                size_t pos = xr() % n;
                switch (xr() % 4) {
                case 0: buf[pos] ^= (uint8_t)(1u << (xr() % 8)); break;
                case 1: buf[pos] = (uint8_t)xr(); break;
                case 2: buf[pos] = 0; break;
                default: if (n < sizeof buf) buf[n++] = (uint8_t)xr(); break;
                }
            }
            LLVMFuzzerTestOneInput(buf, n);
        }
    }
    printf("fuzz_link: %lu runs, no invariant violated\n", runs);
    return 0;
}
#endif
