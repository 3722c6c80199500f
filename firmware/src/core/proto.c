/* servolink v1 framing: see proto.h and firmware/PROTOCOL.md. */
#include "proto.h"

/* CRC-16/MCRF4XX: init 0xFFFF, reflected polynomial 0x8408, no final xor. Same arithmetic as
 * avr-libc's _crc_ccitt_update (written here from its documented equivalent). */
uint16_t sl_crc16_update(uint16_t crc, uint8_t byte)
{
    byte ^= (uint8_t)(crc & 0xFF);
    byte ^= (uint8_t)(byte << 4);
    return (uint16_t)((((uint16_t)byte << 8) | (crc >> 8)) ^ (uint8_t)(byte >> 4) ^ ((uint16_t)byte << 3));
}

uint16_t sl_crc16(const uint8_t *data, uint16_t len)
{
    uint16_t crc = 0xFFFF;
    for (uint16_t i = 0; i < len; i++)
        crc = sl_crc16_update(crc, data[i]);
    return crc;
}

uint16_t sl_cobs_encode(const uint8_t *in, uint16_t len, uint8_t *out)
{
    uint16_t code_pos = 0, o = 1;
    uint8_t code = 1;
    for (uint16_t i = 0; i < len; i++) {
        if (in[i] == 0) {
            out[code_pos] = code;
            code_pos = o++;
            code = 1;
        } else {
            out[o++] = in[i];
            if (++code == 0xFF && i + 1 < len) { /* a full block; start a new one only if data follows */
                out[code_pos] = code;
                code_pos = o++;
                code = 1;
            }
        }
    }
    out[code_pos] = code;
    return o;
}

int16_t sl_cobs_decode(const uint8_t *in, uint16_t len, uint8_t *out, uint16_t out_cap)
{
    uint16_t i = 0, o = 0;
    while (i < len) {
        uint8_t code = in[i++];
        if (code == 0)
            return -1;
        for (uint8_t k = 1; k < code; k++) {
            if (i >= len || in[i] == 0 || o >= out_cap)
                return -1;
            out[o++] = in[i++];
        }
        if (code != 0xFF && i < len) {
            if (o >= out_cap)
                return -1;
            out[o++] = 0;
        }
    }
    return (int16_t)o;
}

uint8_t sl_build_frame(uint8_t type, uint8_t seq, const uint8_t *payload, uint8_t plen, uint8_t *out)
{
    uint8_t raw[SL_MAX_PACKET];
    if (plen > SL_MAX_PAYLOAD)
        return 0;
    raw[0] = type;
    raw[1] = seq;
    for (uint8_t i = 0; i < plen; i++)
        raw[2 + i] = payload[i];
    uint16_t crc = sl_crc16(raw, (uint16_t)(plen + 2));
    raw[2 + plen] = (uint8_t)crc;
    raw[3 + plen] = (uint8_t)(crc >> 8);
    uint16_t n = sl_cobs_encode(raw, (uint16_t)(plen + 4), out);
    out[n] = 0;
    return (uint8_t)(n + 1);
}

void sl_rx_init(sl_rx_t *rx)
{
    rx->len = 0;
    rx->overflow = 0;
}

uint8_t sl_rx_feed(sl_rx_t *rx, uint8_t byte, sl_packet_t *pkt, uint8_t *err)
{
    if (byte != 0) {
        if (rx->len < SL_MAX_ENCODED)
            rx->buf[rx->len++] = byte;
        else
            rx->overflow = 1;
        return SL_RX_NONE;
    }
    /* delimiter: close the frame */
    uint8_t len = rx->len, ovf = rx->overflow;
    rx->len = 0;
    rx->overflow = 0;
    if (ovf) {
        *err = SL_E_TOO_LONG;
        return SL_RX_ERR;
    }
    if (len == 0)
        return SL_RX_NONE;
    uint8_t raw[SL_MAX_ENCODED];
    int16_t n = sl_cobs_decode(rx->buf, len, raw, sizeof raw);
    if (n < 0) {
        *err = SL_E_COBS;
        return SL_RX_ERR;
    }
    if (n < 4) {
        *err = SL_E_SHORT;
        return SL_RX_ERR;
    }
    if (n > SL_MAX_PACKET) {
        *err = SL_E_TOO_LONG;
        return SL_RX_ERR;
    }
    uint16_t crc = sl_crc16(raw, (uint16_t)(n - 2));
    if (sl_get_u16(raw + n - 2) != crc) {
        *err = SL_E_CRC;
        return SL_RX_ERR;
    }
    pkt->type = raw[0];
    pkt->seq = raw[1];
    pkt->plen = (uint8_t)(n - 4);
    for (uint8_t i = 0; i < pkt->plen; i++)
        pkt->payload[i] = raw[2 + i];
    return SL_RX_OK;
}
