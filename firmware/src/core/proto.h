/* servolink v1: COBS framing, CRC-16/MCRF4XX, frame accumulator and packet helpers.
 * Portable C99: compiled by avr-gcc for the ATmega328P and by the host gcc for the unit tests.
 * Normative description: firmware/PROTOCOL.md. */
#ifndef SL_PROTO_H
#define SL_PROTO_H

#include <stdint.h>

#define SL_PROTO_MAJOR 1
#define SL_PROTO_MINOR 1

#define SL_MAX_PACKET 64                        /* decoded: type, seq, payload, crc16 */
#define SL_MAX_PAYLOAD (SL_MAX_PACKET - 4)      /* 60 */
#define SL_MAX_ENCODED (SL_MAX_PACKET + 2)      /* COBS overhead for <= 254 bytes is 1; +1 slack */

/* message types: host -> MCU */
#define SL_T_HELLO 0x01
#define SL_T_PING 0x02
#define SL_T_ARM 0x03
#define SL_T_DISARM 0x04
#define SL_T_GET_STATE 0x05
#define SL_T_SET_ANGLES 0x10
#define SL_T_SET_PULSES 0x11
#define SL_T_CONFIG_CH 0x20
#define SL_T_CONFIG_LINK 0x21
#define SL_T_OSC_SET 0x30
#define SL_T_SET_MODE 0x31
#define SL_T_GAIT_SET 0x40
#define SL_T_GAIT_CONTACTS 0x41
/* MCU -> host */
#define SL_T_NAK 0x7F
#define SL_T_ACK 0x80
#define SL_T_HELLO_ACK 0x81
#define SL_T_EVENT 0x82

/* NAK reasons */
#define SL_E_CRC 1
#define SL_E_COBS 2
#define SL_E_SHORT 3
#define SL_E_TOO_LONG 4
#define SL_E_TYPE 5
#define SL_E_LEN 6
#define SL_E_CHANNEL 7
#define SL_E_NOT_ARMED 8
#define SL_E_VERSION 9
#define SL_E_RANGE 10
#define SL_E_MODE 11

#define SL_SEQ_NONE 0xFF /* seq of a NAK for a frame that could not be decoded */

uint16_t sl_crc16_update(uint16_t crc, uint8_t byte);
uint16_t sl_crc16(const uint8_t *data, uint16_t len);

/* COBS. Encode: out must hold len + len/254 + 1 bytes; returns the encoded length (no delimiter).
 * Decode: returns the decoded length, or -1 on a malformed input (zero byte, code past the end). */
uint16_t sl_cobs_encode(const uint8_t *in, uint16_t len, uint8_t *out);
int16_t sl_cobs_decode(const uint8_t *in, uint16_t len, uint8_t *out, uint16_t out_cap);

/* Build a complete frame (COBS + delimiter) into out (capacity >= SL_MAX_ENCODED + 1).
 * Returns the number of bytes to send, 0 if the payload is too long. */
uint8_t sl_build_frame(uint8_t type, uint8_t seq, const uint8_t *payload, uint8_t plen, uint8_t *out);

/* Frame accumulator: feed bytes; on a delimiter it decodes and checks the frame. */
typedef struct {
    uint8_t buf[SL_MAX_ENCODED];
    uint8_t len;
    uint8_t overflow;
} sl_rx_t;

typedef struct {
    uint8_t type, seq;
    uint8_t plen;
    uint8_t payload[SL_MAX_PAYLOAD];
} sl_packet_t;

#define SL_RX_NONE 0 /* no complete frame yet (or an empty frame: a lone delimiter) */
#define SL_RX_OK 1   /* pkt holds a valid packet */
#define SL_RX_ERR 2  /* *err holds SL_E_COBS / SL_E_CRC / SL_E_SHORT / SL_E_TOO_LONG */

void sl_rx_init(sl_rx_t *rx);
uint8_t sl_rx_feed(sl_rx_t *rx, uint8_t byte, sl_packet_t *pkt, uint8_t *err);

/* little-endian helpers */
static inline uint16_t sl_get_u16(const uint8_t *p) { return (uint16_t)(p[0] | ((uint16_t)p[1] << 8)); }
static inline int16_t sl_get_i16(const uint8_t *p) { return (int16_t)sl_get_u16(p); }
static inline void sl_put_u16(uint8_t *p, uint16_t v) { p[0] = (uint8_t)v; p[1] = (uint8_t)(v >> 8); }
static inline void sl_put_u32(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)v; p[1] = (uint8_t)(v >> 8); p[2] = (uint8_t)(v >> 16); p[3] = (uint8_t)(v >> 24);
}

#endif
