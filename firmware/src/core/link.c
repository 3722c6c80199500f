/* servolink v1 device side. Every request is validated completely before anything changes
 * ("never partially applied"); a rejected request earns a NAK with a reason and changes nothing. */
#include "link.h"

static void send(sl_link_t *l, uint8_t type, uint8_t seq, const uint8_t *p, uint8_t n)
{
    uint8_t frame[SL_MAX_ENCODED + 1];
    uint8_t len = sl_build_frame(type, seq, p, n, frame);
    if (len && l->tx)
        l->tx(l->user, frame, len);
}

static void nak(sl_link_t *l, uint8_t seq, uint8_t code, uint8_t detail)
{
    uint8_t p[2] = {code, detail};
    send(l, SL_T_NAK, seq, p, 2);
}

static void ack(sl_link_t *l, const sl_packet_t *rq, uint8_t *p, uint8_t n)
{
    /* p[0], p[1] are reserved for the request type and the link state */
    p[0] = rq->type;
    p[1] = l->state;
    send(l, SL_T_ACK, rq->seq, p, n);
}

static void event(sl_link_t *l, uint8_t code, uint32_t now)
{
    uint8_t p[6] = {code, l->state};
    sl_put_u32(p + 2, now);
    send(l, SL_T_EVENT, 0, p, 6);
}

static void send_hello_ack(sl_link_t *l, uint8_t seq)
{
    uint8_t p[15];
    p[0] = SL_PROTO_MAJOR;
    p[1] = SL_PROTO_MINOR;
    p[2] = SL_FW_MAJOR;
    p[3] = SL_FW_MINOR;
    p[4] = SL_FW_PATCH;
    p[5] = l->n_ch;
    p[6] = SL_MAX_RATE_HZ;
    sl_put_u16(p + 7, l->wd_ms);
    p[9] = l->caps;
    p[10] = 0x28; /* board id: ATmega328P */
#ifdef SL_BUILD_HASH
    sl_put_u32(p + 11, (uint32_t)SL_BUILD_HASH);
#else
    sl_put_u32(p + 11, 0);
#endif
    send(l, SL_T_HELLO_ACK, seq, p, 15);
}

static uint8_t pulses_on(const sl_link_t *l)
{
    return l->state == SL_ST_ARMED || l->state == SL_ST_HOLD || l->state == SL_ST_PARK;
}

/* A pulse clamped to the channel's window (sl_pulse_window); *clamped (if given) set to 1 if it moved. */
static uint16_t window_clamp(const sl_chan_cfg_t *c, uint16_t us, uint8_t *clamped)
{
    uint16_t lo, hi;
    sl_pulse_window(c, &lo, &hi);
    uint16_t v = us < lo ? lo : us > hi ? hi : us;
    if (clamped && v != us)
        *clamped = 1;
    return v;
}

uint16_t sl_link_output(const sl_link_t *l, uint8_t ch)
{
    if (!pulses_on(l))
        return 0;
    const sl_chan_cfg_t *c = &l->cfg[ch];
    if (l->raw_us[ch])
        return window_clamp(c, l->raw_us[ch], 0);
    uint8_t dummy = 0;
    return sl_cdeg_to_us(c, sl_limit_cdeg(c, l->cur[ch], &dummy), &dummy);
}

/* The only writer of out_us: every output recomputed from (state, mode, config, angle, override) after anything
 * that may change one of them. The memo only skips the arithmetic for an unchanged (config, angle, override). */
static void update_outputs(sl_link_t *l)
{
    for (uint8_t ch = 0; ch < l->n_ch; ch++) {
        uint16_t us = 0;
        if (pulses_on(l)) {
            uint8_t bit = (uint8_t)(1u << ch);
            if (!(l->memo_ok & bit) || l->memo_cdeg[ch] != l->cur[ch] || l->memo_raw[ch] != l->raw_us[ch]) {
                l->memo_cdeg[ch] = l->cur[ch];
                l->memo_raw[ch] = l->raw_us[ch];
                l->memo_us[ch] = sl_link_output(l, ch);
                l->memo_ok |= bit;
            }
            us = l->memo_us[ch];
        }
        if (us != l->out_us[ch]) {
            l->out_us[ch] = us;
            l->out_changed = 1;
        }
    }
}

/* A SET_PULSES override hands over to an angle without a jump: the angle of the pulse being output. */
static void drop_override(sl_link_t *l, uint8_t ch)
{
    if (l->raw_us[ch]) {
        l->cur[ch] = sl_us_to_cdeg(&l->cfg[ch], window_clamp(&l->cfg[ch], l->raw_us[ch], 0));
        l->target[ch] = l->cur[ch];
        l->raw_us[ch] = 0;
    }
}

void sl_link_init(sl_link_t *l, uint8_t n_ch, uint8_t extra_caps, sl_tx_fn tx, sl_contacts_fn contacts, void *user,
                  uint32_t now_ms)
{
    uint8_t *b = (uint8_t *)l;
    for (uint16_t i = 0; i < sizeof *l; i++)
        b[i] = 0;
    l->n_ch = n_ch > SL_MAX_CH ? SL_MAX_CH : n_ch;
    l->caps = (uint8_t)(SL_CAP_OSC | SL_CAP_GAIT | extra_caps);
    for (uint8_t ch = 0; ch < SL_MAX_CH; ch++)
        sl_chan_cfg_default(&l->cfg[ch]);
    l->wd_ms = 500;
    l->park_after_ms = 500;
    l->release_after_ms = 5000;
    l->state = SL_ST_DISARMED;
    l->mode = SL_MODE_STREAM;
    l->tx = tx;
    l->contacts = contacts;
    l->user = user;
    l->last_rx_ms = l->last_slew_ms = now_ms;
    sl_rx_init(&l->rx);
    send_hello_ack(l, 0);
}

/* ---------------------------------------------------------------------------------------------- */
/* The channel run of a SET_ANGLES / SET_PULSES request (first u8, count u8, count x 16-bit values).
 * NAKs (LEN, then CHANNEL) and returns 0 when the length or the channel range is wrong. The LEN detail is the
 * expected length: 2 + 2 count, saturated at 255; 4 (the shortest valid run) without a count or with count 0. */
static uint8_t channel_run(sl_link_t *l, const sl_packet_t *rq, uint8_t *first, uint8_t *count)
{
    const uint8_t *p = rq->payload;
    if (rq->plen < 2 || p[1] == 0 || rq->plen != 2 + 2 * (uint16_t)p[1]) {
        uint16_t want = (rq->plen < 2 || p[1] == 0) ? 4 : 2 + 2 * (uint16_t)p[1];
        nak(l, rq->seq, SL_E_LEN, (uint8_t)(want > 255 ? 255 : want));
        return 0;
    }
    *first = p[0];
    *count = p[1];
    if (*first >= l->n_ch || (uint16_t)*first + *count > l->n_ch) {
        nak(l, rq->seq, SL_E_CHANNEL, *first >= l->n_ch ? *first : l->n_ch);
        return 0;
    }
    return 1;
}

/* Motion frames are taken only in stream mode and while armed; NAKs (MODE, then NOT_ARMED) and
 * returns 0 otherwise. */
static uint8_t may_move(sl_link_t *l, const sl_packet_t *rq)
{
    if (l->mode != SL_MODE_STREAM) {
        nak(l, rq->seq, SL_E_MODE, l->mode);
        return 0;
    }
    if (l->state != SL_ST_ARMED) {
        nak(l, rq->seq, SL_E_NOT_ARMED, l->state);
        return 0;
    }
    return 1;
}

static void do_set_angles(sl_link_t *l, const sl_packet_t *rq)
{
    const uint8_t *p = rq->payload;
    uint8_t first, count;
    if (!channel_run(l, rq, &first, &count))
        return;
    int16_t v[SL_MAX_CH];
    for (uint8_t k = 0; k < count; k++) {
        v[k] = sl_get_i16(p + 2 + 2 * k);
        if (v[k] < -SL_CDEG_MAX || v[k] > SL_CDEG_MAX) {
            nak(l, rq->seq, SL_E_RANGE, k);
            return;
        }
    }
    if (!may_move(l, rq))
        return;
    uint16_t mask = 0;
    for (uint8_t k = 0; k < count; k++) { /* commit all channels together */
        uint8_t ch = (uint8_t)(first + k), c = 0;
        const sl_chan_cfg_t *cfg = &l->cfg[ch];
        int16_t a = sl_limit_cdeg(cfg, v[k], &c);
        if (c || sl_pulse_clamps(cfg, a))
            mask |= (uint16_t)(1u << ch);
        l->target[ch] = a;
        l->raw_us[ch] = 0;
        if (cfg->max_slew_dps == 0)
            l->cur[ch] = a;
    }
    uint8_t out[5];
    sl_put_u16(out + 2, mask);
    out[4] = count;
    ack(l, rq, out, 5); /* accepted and committed: answer first, then map the pulses */
    update_outputs(l);
}

static void do_set_pulses(sl_link_t *l, const sl_packet_t *rq)
{
    const uint8_t *p = rq->payload;
    uint8_t first, count;
    if (!channel_run(l, rq, &first, &count))
        return;
    for (uint8_t k = 0; k < count; k++) {
        uint16_t us = sl_get_u16(p + 2 + 2 * k);
        if (us < SL_US_ABS_MIN || us > SL_US_ABS_MAX) {
            nak(l, rq->seq, SL_E_RANGE, k);
            return;
        }
    }
    if (!may_move(l, rq))
        return;
    uint16_t mask = 0;
    for (uint8_t k = 0; k < count; k++) {
        uint8_t ch = (uint8_t)(first + k);
        uint8_t c = 0; /* inside [min_us, max_us] and the pulses of the soft limits */
        l->raw_us[ch] = window_clamp(&l->cfg[ch], sl_get_u16(p + 2 + 2 * k), &c);
        if (c)
            mask |= (uint16_t)(1u << ch);
    }
    update_outputs(l);
    uint8_t out[5];
    sl_put_u16(out + 2, mask);
    out[4] = count;
    ack(l, rq, out, 5);
}

static void do_config_ch(sl_link_t *l, const sl_packet_t *rq)
{
    const uint8_t *p = rq->payload;
    if (rq->plen != 16) {
        nak(l, rq->seq, SL_E_LEN, 16);
        return;
    }
    if (p[0] >= l->n_ch) {
        nak(l, rq->seq, SL_E_CHANNEL, p[0]);
        return;
    }
    sl_chan_cfg_t c;
    c.min_us = sl_get_u16(p + 1);
    c.max_us = sl_get_u16(p + 3);
    c.trim_cdeg = sl_get_i16(p + 5);
    c.invert = p[7];
    c.lo_cdeg = sl_get_i16(p + 8);
    c.hi_cdeg = sl_get_i16(p + 10);
    c.park_cdeg = sl_get_i16(p + 12);
    c.max_slew_dps = sl_get_u16(p + 14);
    uint8_t bad = sl_chan_cfg_check(&c);
    if (bad) {
        nak(l, rq->seq, SL_E_RANGE, bad);
        return;
    }
    uint8_t ch = p[0], dummy = 0;
    l->cfg[ch] = c;
    l->target[ch] = sl_limit_cdeg(&c, l->target[ch], &dummy);
    l->cur[ch] = sl_limit_cdeg(&c, l->cur[ch], &dummy);
    l->memo_ok &= (uint8_t)~(1u << ch);
    update_outputs(l);
    uint8_t out[2];
    ack(l, rq, out, 2);
}

static void do_config_link(sl_link_t *l, const sl_packet_t *rq)
{
    const uint8_t *p = rq->payload;
    if (rq->plen != 6) {
        nak(l, rq->seq, SL_E_LEN, 6);
        return;
    }
    uint16_t wd = sl_get_u16(p), pa = sl_get_u16(p + 2), re = sl_get_u16(p + 4);
    if (wd < 50 || wd > 10000) {
        nak(l, rq->seq, SL_E_RANGE, 1);
        return;
    }
    if (pa > 60000) {
        nak(l, rq->seq, SL_E_RANGE, 2);
        return;
    }
    if (re > 60000) {
        nak(l, rq->seq, SL_E_RANGE, 3);
        return;
    }
    l->wd_ms = wd;
    l->park_after_ms = pa;
    l->release_after_ms = re;
    uint8_t out[2];
    ack(l, rq, out, 2);
}

static void do_osc_set(sl_link_t *l, const sl_packet_t *rq)
{
    const uint8_t *p = rq->payload;
    if (rq->plen != 9 && rq->plen != 13) {
        nak(l, rq->seq, SL_E_LEN, 9);
        return;
    }
    uint8_t ch = p[0];
    if (ch >= l->n_ch) {
        nak(l, rq->seq, SL_E_CHANNEL, ch);
        return;
    }
    sl_osc_t o;
    o.amp_cdeg = sl_get_i16(p + 1);
    o.offset_cdeg = sl_get_i16(p + 3);
    o.period_ms = sl_get_u16(p + 5);
    o.phase_cdeg = sl_get_u16(p + 7);
    o.gain_pos = rq->plen == 13 ? sl_get_i16(p + 9) : SL_GAIN_ONE;
    o.gain_neg = rq->plen == 13 ? sl_get_i16(p + 11) : SL_GAIN_ONE;
    const sl_chan_cfg_t *c = &l->cfg[ch];
    if (o.amp_cdeg < 0 || o.amp_cdeg > SL_CDEG_MAX) {
        nak(l, rq->seq, SL_E_RANGE, 1);
        return;
    }
    int32_t v_lo = (int32_t)o.offset_cdeg - o.amp_cdeg, v_hi = (int32_t)o.offset_cdeg + o.amp_cdeg;
    if (v_lo < -SL_CDEG_MAX || v_hi > SL_CDEG_MAX) {
        nak(l, rq->seq, SL_E_RANGE, 2);
        return;
    }
    if ((o.gain_pos < 0 && o.gain_neg > 0) || (o.gain_pos > 0 && o.gain_neg < 0)) {
        nak(l, rq->seq, SL_E_RANGE, 5); /* g must be monotonic: its extremes are then the swing's ends */
        return;
    }
    int16_t g_lo = sl_osc_gain(&o, (int16_t)v_lo), g_hi = sl_osc_gain(&o, (int16_t)v_hi);
    if ((g_lo < g_hi ? g_lo : g_hi) < c->lo_cdeg || (g_lo < g_hi ? g_hi : g_lo) > c->hi_cdeg) {
        nak(l, rq->seq, SL_E_RANGE, 2); /* the swing must stay inside the channel's limits */
        return;
    }
    if (o.period_ms != 0 && o.period_ms < 2 * (1000 / SL_MAX_RATE_HZ)) {
        nak(l, rq->seq, SL_E_RANGE, 3);
        return;
    }
    if (o.phase_cdeg >= 36000) {
        nak(l, rq->seq, SL_E_RANGE, 4);
        return;
    }
    l->osc[ch] = o;
    l->osc_on |= (uint8_t)(1u << ch);
    uint8_t out[2];
    ack(l, rq, out, 2);
}

static void do_set_mode(sl_link_t *l, const sl_packet_t *rq, uint32_t now)
{
    if (rq->plen != 1) {
        nak(l, rq->seq, SL_E_LEN, 1);
        return;
    }
    uint8_t m = rq->payload[0];
    if (m > SL_MODE_GAIT) {
        nak(l, rq->seq, SL_E_RANGE, 1);
        return;
    }
    if (m == SL_MODE_GAIT && l->gait_n == 0) {
        nak(l, rq->seq, SL_E_MODE, m); /* GAIT_SET first */
        return;
    }
    l->mode = m;
    l->osc_t0 = now;
    for (uint8_t ch = 0; ch < l->n_ch; ch++)
        drop_override(l, ch);
    uint8_t out[6];
    sl_put_u32(out + 2, now); /* the time origin of the oscillators */
    ack(l, rq, out, 6);
    update_outputs(l);
}

static void gait_apply(sl_link_t *l)
{
    sl_gait_step(l->gait_air, l->gait_n, l->gait_n1, l->gait_n2, l->gait_flags & SL_GAIT_CLOSED, l->gait_act);
}

static void do_gait_set(sl_link_t *l, const sl_packet_t *rq)
{
    const uint8_t *p = rq->payload;
    if (rq->plen != 9) {
        nak(l, rq->seq, SL_E_LEN, 9);
        return;
    }
    uint8_t n = p[0], n1 = p[1], n2 = p[2], flags = p[3], first = p[4];
    int16_t inflate = sl_get_i16(p + 5), vent = sl_get_i16(p + 7);
    if (n < 1 || n > SL_GAIT_MAX_CELLS || ((flags & SL_GAIT_PINS) && n > l->pin_cells)) {
        nak(l, rq->seq, SL_E_RANGE, 1);
        return;
    }
    if (n1 >= n) {
        nak(l, rq->seq, SL_E_RANGE, 2);
        return;
    }
    if (n2 >= n) {
        nak(l, rq->seq, SL_E_RANGE, 3);
        return;
    }
    if (flags & ~(SL_GAIT_CLOSED | SL_GAIT_PINS) || ((flags & SL_GAIT_PINS) && !l->pin_cells)) {
        nak(l, rq->seq, SL_E_RANGE, 4);
        return;
    }
    if (first >= n || ((flags & SL_GAIT_PINS) && first != 0)) {
        nak(l, rq->seq, SL_E_RANGE, 5);
        return;
    }
    for (uint8_t k = 0; k < 2; k++) {
        int16_t a = k ? vent : inflate;
        for (uint8_t ch = 0; ch < l->n_ch && first + ch < n; ch++) {
            if (a < l->cfg[ch].lo_cdeg || a > l->cfg[ch].hi_cdeg) {
                nak(l, rq->seq, SL_E_RANGE, (uint8_t)(6 + k));
                return;
            }
        }
    }
    l->gait_n = n;
    l->gait_n1 = n1;
    l->gait_n2 = n2;
    l->gait_flags = flags;
    l->gait_first = first;
    l->gait_inflate = inflate;
    l->gait_vent = vent;
    for (uint8_t b = 0; b < 8; b++)
        l->gait_air[b] = 0xFF; /* all in the air until the first reading: nobody fires */
    gait_apply(l);
    uint8_t out[2];
    ack(l, rq, out, 2);
}

static void do_gait_contacts(sl_link_t *l, const sl_packet_t *rq)
{
    if (l->gait_n == 0) {
        nak(l, rq->seq, SL_E_MODE, l->mode);
        return;
    }
    uint8_t nb = (uint8_t)((l->gait_n + 7) / 8);
    if (rq->plen != nb) {
        nak(l, rq->seq, SL_E_LEN, nb);
        return;
    }
    if (l->gait_flags & SL_GAIT_PINS) {
        nak(l, rq->seq, SL_E_MODE, l->mode); /* the contacts come from the pins */
        return;
    }
    for (uint8_t b = 0; b < nb; b++)
        l->gait_air[b] = rq->payload[b];
    gait_apply(l);
    uint8_t out[2 + 8];
    for (uint8_t b = 0; b < nb; b++)
        out[2 + b] = l->gait_act[b];
    ack(l, rq, out, (uint8_t)(2 + nb));
}

static void arm(sl_link_t *l)
{
    uint8_t was_off = !pulses_on(l);
    for (uint8_t ch = 0; ch < l->n_ch; ch++) {
        if (was_off) { /* the position is unknown: start from the park angle */
            l->cur[ch] = l->cfg[ch].park_cdeg;
            l->raw_us[ch] = 0;
        }
        drop_override(l, ch); /* pulses on (HOLD, PARK, re-ARM): continue from the pulse being output */
        l->target[ch] = l->cur[ch];
    }
    l->state = SL_ST_ARMED;
    l->mode = SL_MODE_STREAM;
    update_outputs(l);
}

static uint8_t next_seq(uint8_t s)
{
    return (uint8_t)(s >= 254 ? 1 : s + 1);
}

static void dispatch(sl_link_t *l, const sl_packet_t *rq, uint32_t now)
{
    uint8_t out[4 + 2 * SL_MAX_CH + 12];
    l->rx_ok++;
    l->last_rx_ms = now; /* any valid frame proves the host is alive */
    if (l->have_seq && rq->seq != next_seq(l->last_seq))
        l->seq_gaps++;
    l->last_seq = rq->seq;
    l->have_seq = 1;
    /* requests without a payload: PING, ARM, DISARM, GET_STATE (NAK LEN, detail 0: nothing changes) */
    if ((rq->type == SL_T_PING || rq->type == SL_T_ARM || rq->type == SL_T_DISARM || rq->type == SL_T_GET_STATE) &&
        rq->plen != 0) {
        nak(l, rq->seq, SL_E_LEN, 0);
        return;
    }
    switch (rq->type) {
    case SL_T_HELLO: /* another major first (a later protocol may lengthen HELLO), then exactly 3 bytes */
        if (rq->plen >= 1 && rq->payload[0] != SL_PROTO_MAJOR)
            nak(l, rq->seq, SL_E_VERSION, SL_PROTO_MAJOR);
        else if (rq->plen != 3)
            nak(l, rq->seq, SL_E_LEN, 3);
        else
            send_hello_ack(l, rq->seq);
        break;
    case SL_T_PING:
        sl_put_u32(out + 2, now);
        sl_put_u16(out + 6, l->rx_ok);
        sl_put_u16(out + 8, l->crc_err);
        sl_put_u16(out + 10, l->framing_err);
        sl_put_u16(out + 12, l->seq_gaps);
        out[14] = l->wdt_trips;
        out[15] = l->mode;
        out[16] = l->servo_fault_on;
        out[17] = l->servo_faults;
        ack(l, rq, out, 18);
        break;
    case SL_T_ARM:
        arm(l);
        ack(l, rq, out, 2);
        break;
    case SL_T_DISARM:
        l->state = SL_ST_DISARMED;
        l->mode = SL_MODE_STREAM;
        update_outputs(l);
        ack(l, rq, out, 2);
        break;
    case SL_T_GET_STATE:
        out[2] = l->mode;
        out[3] = l->n_ch;
        for (uint8_t ch = 0; ch < l->n_ch; ch++)
            sl_put_u16(out + 4 + 2 * ch, l->out_us[ch]);
        ack(l, rq, out, (uint8_t)(4 + 2 * l->n_ch));
        break;
    case SL_T_SET_ANGLES:
        do_set_angles(l, rq);
        break;
    case SL_T_SET_PULSES:
        do_set_pulses(l, rq);
        break;
    case SL_T_CONFIG_CH:
        do_config_ch(l, rq);
        break;
    case SL_T_CONFIG_LINK:
        do_config_link(l, rq);
        break;
    case SL_T_OSC_SET:
        do_osc_set(l, rq);
        break;
    case SL_T_SET_MODE:
        do_set_mode(l, rq, now);
        break;
    case SL_T_GAIT_SET:
        do_gait_set(l, rq);
        break;
    case SL_T_GAIT_CONTACTS:
        do_gait_contacts(l, rq);
        break;
    default:
        nak(l, rq->seq, SL_E_TYPE, rq->type);
        break;
    }
}

void sl_link_feed(sl_link_t *l, uint8_t byte, uint32_t now_ms)
{
    sl_packet_t pkt;
    uint8_t err = 0;
    uint8_t r = sl_rx_feed(&l->rx, byte, &pkt, &err);
    if (r == SL_RX_OK) {
        dispatch(l, &pkt, now_ms);
    } else if (r == SL_RX_ERR) {
        if (err == SL_E_CRC)
            l->crc_err++;
        else
            l->framing_err++;
        nak(l, SL_SEQ_NONE, err, 0);
    }
}

void sl_link_servo_status(sl_link_t *l, uint8_t ok, uint32_t now)
{
    if (ok) {
        l->servo_fault_on = 0;
        return;
    }
    if (l->servo_faults < 255)
        l->servo_faults++;
    if (!l->servo_fault_on) {
        l->servo_fault_on = 1;
        event(l, SL_EV_SERVO_FAULT, now);
    }
}

void sl_link_tick(sl_link_t *l, uint32_t now)
{
    /* link watchdog: ARMED -> HOLD -> PARK -> RELEASED */
    if (l->state == SL_ST_ARMED && (uint32_t)(now - l->last_rx_ms) > l->wd_ms) {
        l->state = SL_ST_HOLD;
        l->trip_ms = now;
        if (l->wdt_trips < 255)
            l->wdt_trips++;
        for (uint8_t ch = 0; ch < l->n_ch; ch++)
            l->target[ch] = l->cur[ch]; /* keep the last pulse, a SET_PULSES override included (section 6) */
        event(l, SL_EV_HOLD, now);
    }
    if (l->state == SL_ST_HOLD && (uint32_t)(now - l->trip_ms) >= l->park_after_ms) {
        l->state = SL_ST_PARK;
        for (uint8_t ch = 0; ch < l->n_ch; ch++) {
            drop_override(l, ch); /* ramp from the held pulse */
            l->target[ch] = l->cfg[ch].park_cdeg;
        }
        event(l, SL_EV_PARK, now);
    }
    if (l->state == SL_ST_PARK &&
        (uint32_t)(now - l->trip_ms) >= (uint32_t)l->park_after_ms + l->release_after_ms) {
        l->state = SL_ST_RELEASED;
        event(l, SL_EV_RELEASE, now);
    }

    uint32_t dt = now - l->last_slew_ms;
    if (dt >= SL_SLEW_PERIOD_MS) {
        if (dt > 100)
            dt = 100;
        l->last_slew_ms = now;
        if (l->state == SL_ST_ARMED && l->mode == SL_MODE_OSC) {
            for (uint8_t ch = 0; ch < l->n_ch; ch++)
                if (l->osc_on & (1u << ch)) {
                    uint8_t dummy = 0; /* OSC_SET checked the swing against the limits */
                    l->target[ch] = sl_limit_cdeg(
                        &l->cfg[ch], sl_osc_gain(&l->osc[ch], sl_osc_value(&l->osc[ch], now - l->osc_t0)), &dummy);
                }
        } else if (l->state == SL_ST_ARMED && l->mode == SL_MODE_GAIT) {
            if ((l->gait_flags & SL_GAIT_PINS) && l->contacts) {
                l->contacts(l->user, l->gait_air, l->gait_n);
                gait_apply(l);
            }
            for (uint8_t ch = 0; ch < l->n_ch; ch++) {
                uint8_t cell = (uint8_t)(l->gait_first + ch);
                if (cell < l->gait_n)
                    l->target[ch] = ((l->gait_act[cell >> 3] >> (cell & 7)) & 1) ? l->gait_inflate : l->gait_vent;
            }
        }
        for (uint8_t ch = 0; ch < l->n_ch; ch++) {
            uint8_t dummy = 0; /* the limits of now, whatever they were when a generator or a target was set */
            if (l->state == SL_ST_PARK) /* the park angle of now (a CONFIG_CH may move it while parking) */
                l->target[ch] = l->cfg[ch].park_cdeg;
            l->target[ch] = sl_limit_cdeg(&l->cfg[ch], l->target[ch], &dummy);
            uint16_t rate = l->cfg[ch].max_slew_dps;
            if (l->state == SL_ST_PARK && rate == 0)
                rate = SL_PARK_DEFAULT_DPS;
            l->cur[ch] = sl_slew(l->cur[ch], l->target[ch], rate, (uint16_t)dt);
        }
    }
    update_outputs(l);
}
