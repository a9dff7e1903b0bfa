/*
 * vest_protocol.h -- THE definition of the serial protocol between the PC (vest bridge) and the
 * tactile vest's microcontroller. Plain C99 / C++, header-only, no allocation, no OS calls: the
 * same file is compiled into the ROS bridge (assistive_tactile_core), the simulated vest and the
 * Arduino sketch (firmware/vest/vest.ino includes it through the symlink
 * firmware/vest/vest_protocol.h). Change it here and both sides change.
 *
 * Packet (9 bytes, both directions, all fields uint8):
 *
 *   byte 0  SYNC      0xA5
 *   byte 1  TYPE      0x01 = COMMAND (PC -> vest), 0x02 = STATUS (vest -> PC)
 *   byte 2  SEQ       sequence number, +1 per packet sent (wraps at 255); a STATUS echoes the SEQ
 *                     of the last COMMAND the vest accepted
 *   byte 3  MOTORS    bit i set = motor i on (bit 0 left shoulder, 1 right shoulder,
 *                     2 left waist, 3 right waist); bits 4..7 must be 0
 *   byte 4  I0        PWM duty of motor 0 (0..255), used only when its bit is set
 *   byte 5  I1        motor 1
 *   byte 6  I2        motor 2
 *   byte 7  I3        motor 3
 *   byte 8  CRC       CRC-8 (polynomial 0x07, init 0x00, no reflection, no final xor,
 *                     i.e. CRC-8/SMBUS) over bytes 1..7
 *
 * Motor i is driven at  (MOTORS >> i) & 1 ? Ii : 0.
 * A COMMAND is the complete desired state (not a delta), so a lost packet is healed by the next
 * one. The PC re-sends it at a fixed rate (default 20 Hz). The vest switches every motor off when
 * no valid COMMAND arrived for VEST_WATCHDOG_MS, and answers every accepted COMMAND with a
 * STATUS carrying what the motors now do (the PC uses it as link proof and on diagnostics).
 * Receivers scan the byte stream for SYNC, and on a bad CRC or reserved bits resume scanning at
 * the byte after the rejected SYNC, so garbage and truncated packets cost at most one packet.
 */
#ifndef ASSISTIVE_TACTILE_VEST_PROTOCOL_H
#define ASSISTIVE_TACTILE_VEST_PROTOCOL_H

#include <stdint.h>
#include <string.h>

#ifdef __cplusplus
extern "C" {
#endif

#define VEST_SYNC 0xA5u
#define VEST_TYPE_COMMAND 0x01u
#define VEST_TYPE_STATUS 0x02u
#define VEST_PACKET_SIZE 9u
#define VEST_NUM_MOTORS 4u
#define VEST_WATCHDOG_MS 500u

/* Motor indices (match assistive_msgs/TactileCue). */
#define VEST_LEFT_SHOULDER 0u
#define VEST_RIGHT_SHOULDER 1u
#define VEST_LEFT_WAIST 2u
#define VEST_RIGHT_WAIST 3u

typedef struct
{
  uint8_t type;
  uint8_t seq;
  uint8_t motors;                       /* bit mask, bits 0..3 */
  uint8_t intensity[VEST_NUM_MOTORS];   /* 0..255 */
} vest_packet_t;

/* CRC-8/SMBUS: poly 0x07, init 0x00. Bitwise: small enough for the ATmega (no table in RAM). */
static inline uint8_t vest_crc8(const uint8_t* data, uint8_t len)
{
  uint8_t crc = 0x00u;
  uint8_t i, b;
  for (i = 0; i < len; ++i)
  {
    crc ^= data[i];
    for (b = 0; b < 8u; ++b)
      crc = (uint8_t)((crc & 0x80u) ? (uint8_t)((crc << 1) ^ 0x07u) : (uint8_t)(crc << 1));
  }
  return crc;
}

/* Writes VEST_PACKET_SIZE bytes to out. */
static inline void vest_encode(const vest_packet_t* p, uint8_t* out)
{
  uint8_t i;
  out[0] = (uint8_t)VEST_SYNC;
  out[1] = p->type;
  out[2] = p->seq;
  out[3] = (uint8_t)(p->motors & 0x0Fu);
  for (i = 0; i < VEST_NUM_MOTORS; ++i)
    out[4 + i] = p->intensity[i];
  out[8] = vest_crc8(out + 1, 7u);
}

/* Checks one complete candidate packet; returns 1 and fills p when it is valid. */
static inline int vest_decode(const uint8_t* in, vest_packet_t* p)
{
  uint8_t i;
  if (in[0] != VEST_SYNC)
    return 0;
  if (in[1] != VEST_TYPE_COMMAND && in[1] != VEST_TYPE_STATUS)
    return 0;
  if ((in[3] & 0xF0u) != 0u)
    return 0;
  if (vest_crc8(in + 1, 7u) != in[8])
    return 0;
  p->type = in[1];
  p->seq = in[2];
  p->motors = in[3];
  for (i = 0; i < VEST_NUM_MOTORS; ++i)
    p->intensity[i] = in[4 + i];
  return 1;
}

/* Effective duty of motor i of a packet. */
static inline uint8_t vest_motor_duty(const vest_packet_t* p, uint8_t i)
{
  return ((p->motors >> i) & 1u) ? p->intensity[i] : (uint8_t)0u;
}

/* ---- Streaming parser: feed bytes one at a time. ---- */
typedef struct
{
  uint8_t buf[VEST_PACKET_SIZE];
  uint8_t len;
  uint16_t packets;   /* valid packets (wraps) */
  uint16_t rejected;  /* candidate packets that failed the check (wraps) */
  uint16_t skipped;   /* bytes dropped while looking for SYNC (wraps) */
} vest_parser_t;

static inline void vest_parser_init(vest_parser_t* ps)
{
  memset(ps, 0, sizeof(*ps));
}

/* Drops buf[0] and re-scans the rest for the next SYNC. */
static inline void vest_parser_resync(vest_parser_t* ps)
{
  uint8_t start = 1u, i;
  while (start < ps->len && ps->buf[start] != VEST_SYNC)
    ++start;
  ps->skipped = (uint16_t)(ps->skipped + (start - 1u));
  for (i = 0; start + i < ps->len; ++i)
    ps->buf[i] = ps->buf[start + i];
  ps->len = (uint8_t)(ps->len - start);
}

/* Feeds one byte. Returns 1 when it completed a valid packet (copied to *out), else 0. */
static inline int vest_parser_feed(vest_parser_t* ps, uint8_t byte, vest_packet_t* out)
{
  if (ps->len == 0u && byte != VEST_SYNC)
  {
    ps->skipped++;
    return 0;
  }
  ps->buf[ps->len++] = byte;
  while (ps->len == VEST_PACKET_SIZE)
  {
    if (vest_decode(ps->buf, out))
    {
      ps->len = 0u;
      ps->packets++;
      return 1;
    }
    ps->rejected++;
    vest_parser_resync(ps); /* the rest may hold the start of the real packet */
  }
  return 0;
}

/* ---- The vest's behaviour (the firmware's loop, also run by the simulated vest). ---- */
typedef struct
{
  vest_parser_t parser;
  uint8_t duty[VEST_NUM_MOTORS]; /* what the PWM outputs drive now */
  uint8_t motors;                /* bit mask of motors with duty > 0 */
  uint8_t last_seq;              /* SEQ of the last accepted COMMAND */
  uint8_t have_command;          /* 1 once a COMMAND was accepted since the last timeout */
  uint32_t last_command_ms;
  uint16_t timeouts;             /* watchdog trips (wraps) */
} vest_firmware_t;

static inline void vest_firmware_init(vest_firmware_t* fw, uint32_t now_ms)
{
  memset(fw, 0, sizeof(*fw));
  vest_parser_init(&fw->parser);
  fw->last_command_ms = now_ms;
}

static inline void vest_firmware_all_off(vest_firmware_t* fw)
{
  uint8_t i;
  for (i = 0; i < VEST_NUM_MOTORS; ++i)
    fw->duty[i] = 0u;
  fw->motors = 0u;
}

/* Feeds one received byte. Returns 1 when a valid COMMAND was applied; then *status holds the
 * STATUS packet to send back. STATUS packets and anything invalid are ignored. */
static inline int vest_firmware_feed(vest_firmware_t* fw, uint8_t byte, uint32_t now_ms,
                                     vest_packet_t* status)
{
  vest_packet_t p;
  uint8_t i;
  if (!vest_parser_feed(&fw->parser, byte, &p) || p.type != VEST_TYPE_COMMAND)
    return 0;
  fw->motors = 0u;
  for (i = 0; i < VEST_NUM_MOTORS; ++i)
  {
    fw->duty[i] = vest_motor_duty(&p, i);
    if (fw->duty[i] > 0u)
      fw->motors = (uint8_t)(fw->motors | (1u << i));
  }
  fw->last_seq = p.seq;
  fw->have_command = 1u;
  fw->last_command_ms = now_ms;
  status->type = VEST_TYPE_STATUS;
  status->seq = fw->last_seq;
  status->motors = fw->motors;
  for (i = 0; i < VEST_NUM_MOTORS; ++i)
    status->intensity[i] = fw->duty[i];
  return 1;
}

/* Watchdog; call every loop. Returns 1 when it just switched the motors off. Unsigned
 * subtraction keeps it right across the millis() wrap (49.7 days). */
static inline int vest_firmware_tick(vest_firmware_t* fw, uint32_t now_ms)
{
  if (fw->have_command && (uint32_t)(now_ms - fw->last_command_ms) > VEST_WATCHDOG_MS)
  {
    vest_firmware_all_off(fw);
    fw->have_command = 0u;
    fw->timeouts++;
    return 1;
  }
  return 0;
}

#ifdef __cplusplus
} /* extern "C" */
#endif

#endif /* ASSISTIVE_TACTILE_VEST_PROTOCOL_H */
