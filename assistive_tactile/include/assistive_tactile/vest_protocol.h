/*
 * vest_protocol.h -- THE definition of the serial protocol between the PC (vest bridge) and the
 * tactile vest's microcontroller. Plain C99 / C++, header-only, no allocation, no OS calls: the
 * same file is compiled into the ROS bridge (assistive_tactile_core), the simulated vest and the
 * Arduino sketch (firmware/vest/vest.ino includes it through the symlink
 * firmware/vest/vest_protocol.h). Change it here and both sides change.
 *
 * Protocol version 2 (version 1 was SYNC 0xA5 + CRC-8; it let noise through as false COMMANDs).
 *
 * Packet (14 bytes before framing, both directions):
 *
 *   byte 0    VERSION   VEST_PROTOCOL_VERSION (2); a receiver rejects and counts other versions
 *   byte 1    TYPE      0x01 = COMMAND (PC -> vest), 0x02 = STATUS (vest -> PC)
 *   byte 2    SEQ       sequence number, +1 per packet sent (wraps at 255); a STATUS echoes the
 *                       SEQ of the last COMMAND the vest accepted
 *   byte 3    MOTORS    bit i set = motor i on (bit 0 left shoulder, 1 right shoulder,
 *                       2 left waist, 3 right waist); bits 4..7 must be 0
 *   byte 4-7  I0..I3    PWM duty of motor i (0..255), used only when its bit is set
 *   byte 8-9  TTL_MS    uint16, low byte first. COMMAND: the vest drives these duties for at
 *                       most TTL_MS ms after it received the packet, then switches every motor
 *                       off by itself (capped by VEST_WATCHDOG_MS); the PC sets it from the cue's
 *                       stamps, so a cue ends on time even when the PC stalls. STATUS: 0.
 *   byte 10-13 CRC      CRC-32C (Castagnoli: poly 0x1EDC6F41 reflected, init and final xor
 *                       0xFFFFFFFF; check value 0xE3069283) over bytes 0..9, low byte first.
 *                       (CRC-16/CCITT-FALSE let 1 damaged frame through per ~3e7 random
 *                       corruptions in tactile_benchmark; 32 bits make that 65536 times rarer.)
 *
 * Framing: COBS (Consistent Overhead Byte Stuffing). The 14 bytes are COBS-encoded (15 bytes, no
 * 0x00 inside) and sent between two 0x00 delimiters: 17 bytes on the wire,
 *
 *   0x00  COBS(packet)  0x00
 *
 * A receiver collects the bytes between delimiters into a frame and accepts it only when the COBS
 * structure is valid, the CRC matches, VERSION is ours, the decoded length is exactly 14 and the
 * fields are legal. Since a frame starts only at a delimiter, a packet is never read at a shifted
 * offset (the SYNC scan of version 1 could); garbage, a truncated or a shifted packet cost that
 * frame only, and the next delimiter resynchronises. The leading delimiter ends any garbage
 * before the packet, so the packet after a burst of noise still arrives. The CRC is checked
 * before VERSION, so a counted version mismatch is a real peer of another version, not noise;
 * the CRC sits at the end of every version's frame for that reason.
 *
 * Motor i is driven at  (MOTORS >> i) & 1 ? Ii : 0.
 * A COMMAND is the complete desired state (not a delta), so a lost packet is healed by the next
 * one. The PC re-sends it at a fixed rate (default 20 Hz). The vest switches every motor off when
 * the last COMMAND's TTL ran out or no valid COMMAND arrived for VEST_WATCHDOG_MS (whichever comes
 * first), and answers every accepted COMMAND with a
 * STATUS carrying what the motors now do (the PC uses it as link proof and on diagnostics).
 */
#ifndef ASSISTIVE_TACTILE_VEST_PROTOCOL_H
#define ASSISTIVE_TACTILE_VEST_PROTOCOL_H

#include <stdint.h>
#include <string.h>

#ifdef __cplusplus
extern "C" {
#endif

#define VEST_PROTOCOL_VERSION 2u
#define VEST_DELIMITER 0x00u
#define VEST_TYPE_COMMAND 0x01u
#define VEST_TYPE_STATUS 0x02u
#define VEST_CRC_SIZE 4u
#define VEST_RAW_SIZE 14u                       /* VERSION .. CRC, before COBS */
#define VEST_COBS_SIZE (VEST_RAW_SIZE + 1u)     /* COBS adds one byte to frames under 254 bytes */
#define VEST_PACKET_SIZE (VEST_COBS_SIZE + 2u)  /* on the wire, with both delimiters: 17 */
#define VEST_MAX_FRAME 32u  /* longest frame a receiver buffers; longer = garbage, dropped */
#define VEST_NUM_MOTORS 4u
#define VEST_WATCHDOG_MS 500u

/* vest_firmware_feed's results */
#define VEST_FEED_NONE 0
#define VEST_FEED_APPLIED 1        /* a valid COMMAND was applied: send *status back */
#define VEST_FEED_VERSION_REPLY 2  /* a CRC-valid frame of another version: nothing applied; send
                                      *status back so that peer learns this vest's version */

/* vest_firmware_tick's results */
#define VEST_TICK_NONE 0
#define VEST_TICK_WATCHDOG 1  /* no valid COMMAND for VEST_WATCHDOG_MS: all off */
#define VEST_TICK_EXPIRED 2   /* the last COMMAND's TTL ran out: all off */

/* Motor indices (match assistive_msgs/TactileCue). */
#define VEST_LEFT_SHOULDER 0u
#define VEST_RIGHT_SHOULDER 1u
#define VEST_LEFT_WAIST 2u
#define VEST_RIGHT_WAIST 3u

/* Why a frame was rejected (vest_decode_frame's result). */
#define VEST_FRAME_OK 0
#define VEST_FRAME_COBS 1     /* COBS structure broken (a code byte points past the end) */
#define VEST_FRAME_SHORT 2    /* too short to hold a CRC */
#define VEST_FRAME_CRC 3      /* CRC mismatch */
#define VEST_FRAME_VERSION 4  /* CRC fine, another protocol version */
#define VEST_FRAME_LENGTH 5   /* our version, wrong length */
#define VEST_FRAME_FIELD 6    /* unknown TYPE or reserved MOTORS bits set */

typedef struct
{
  uint8_t type;
  uint8_t seq;
  uint8_t motors;                       /* bit mask, bits 0..3 */
  uint8_t intensity[VEST_NUM_MOTORS];   /* 0..255 */
  uint16_t ttl_ms;                      /* COMMAND: drive at most this long after receipt */
} vest_packet_t;

/* CRC-32C (Castagnoli), reflected, init/xorout 0xFFFFFFFF. Bitwise: no table in the ATmega's
 * RAM (about 50 us per packet at 16 MHz). */
static inline uint32_t vest_crc32c(const uint8_t* data, uint8_t len)
{
  uint32_t crc = 0xFFFFFFFFul;
  uint8_t i, b;
  for (i = 0; i < len; ++i)
  {
    crc ^= data[i];
    for (b = 0; b < 8u; ++b)
      crc = (crc & 1ul) ? ((crc >> 1) ^ 0x82F63B78ul) : (crc >> 1);
  }
  return crc ^ 0xFFFFFFFFul;
}

/* COBS-encodes len (< 254) bytes; returns the encoded length (len + 1). No 0x00 in the output. */
static inline uint8_t vest_cobs_encode(const uint8_t* in, uint8_t len, uint8_t* out)
{
  uint8_t code_at = 0u, o = 1u, code = 1u, i;
  for (i = 0; i < len; ++i)
  {
    if (in[i] == 0u)
    {
      out[code_at] = code;
      code_at = o++;
      code = 1u;
    }
    else
    {
      out[o++] = in[i];
      ++code;
    }
  }
  out[code_at] = code;
  return o;
}

/* COBS-decodes one frame (no delimiters, no 0x00 inside); returns the decoded length, or -1 when
 * the structure is broken. out must hold len bytes. */
static inline int vest_cobs_decode(const uint8_t* in, uint8_t len, uint8_t* out)
{
  uint8_t i = 0u, o = 0u, code, k;
  while (i < len)
  {
    code = in[i++];
    if (code == 0u || (uint8_t)(code - 1u) > (uint8_t)(len - i))
      return -1;
    for (k = 1u; k < code; ++k)
      out[o++] = in[i++];
    if (code != 0xFFu && i < len)
      out[o++] = 0u;
  }
  return (int)o;
}

/* Frames len (<= VEST_MAX_FRAME - VEST_CRC_SIZE) payload bytes: appends the CRC (low byte
 * first), COBS-encodes, adds both delimiters. out must hold len + 7 bytes; returns the bytes
 * written (0 when len is too long). */
static inline uint8_t vest_frame(const uint8_t* payload, uint8_t len, uint8_t* out)
{
  uint8_t raw[VEST_MAX_FRAME];
  uint8_t n;
  uint32_t crc;
  if (len > VEST_MAX_FRAME - VEST_CRC_SIZE)
    return 0u;
  crc = vest_crc32c(payload, len);
  memcpy(raw, payload, len);
  raw[len] = (uint8_t)(crc & 0xFFu);
  raw[len + 1] = (uint8_t)((crc >> 8) & 0xFFu);
  raw[len + 2] = (uint8_t)((crc >> 16) & 0xFFu);
  raw[len + 3] = (uint8_t)((crc >> 24) & 0xFFu);
  out[0] = (uint8_t)VEST_DELIMITER;
  n = vest_cobs_encode(raw, (uint8_t)(len + VEST_CRC_SIZE), out + 1);
  out[n + 1u] = (uint8_t)VEST_DELIMITER;
  return (uint8_t)(n + 2u);
}

/* Writes VEST_PACKET_SIZE bytes (delimiter, COBS frame, delimiter) to out; VERSION is ours. */
static inline void vest_encode(const vest_packet_t* p, uint8_t* out)
{
  uint8_t raw[VEST_RAW_SIZE - VEST_CRC_SIZE];
  uint8_t i;
  raw[0] = (uint8_t)VEST_PROTOCOL_VERSION;
  raw[1] = p->type;
  raw[2] = p->seq;
  raw[3] = (uint8_t)(p->motors & 0x0Fu);
  for (i = 0; i < VEST_NUM_MOTORS; ++i)
    raw[4 + i] = p->intensity[i];
  raw[8] = (uint8_t)(p->ttl_ms & 0xFFu);
  raw[9] = (uint8_t)(p->ttl_ms >> 8);
  vest_frame(raw, (uint8_t)(VEST_RAW_SIZE - VEST_CRC_SIZE), out);
}

/* Checks one frame (the bytes between two delimiters). Returns VEST_FRAME_OK and fills p when it
 * is a valid packet of our version; else the reason. *version gets the VERSION byte of a
 * CRC-valid frame (for mismatch reports); it may be NULL. */
static inline int vest_decode_frame(const uint8_t* frame, uint8_t len, vest_packet_t* p, uint8_t* version)
{
  uint8_t raw[VEST_MAX_FRAME];
  uint8_t i;
  int n;
  uint32_t crc;
  if (len > VEST_MAX_FRAME)
    return VEST_FRAME_LENGTH;
  n = vest_cobs_decode(frame, len, raw);
  if (n < 0)
    return VEST_FRAME_COBS;
  if (n < (int)VEST_CRC_SIZE + 1)
    return VEST_FRAME_SHORT;
  crc = vest_crc32c(raw, (uint8_t)(n - (int)VEST_CRC_SIZE));
  if (raw[n - 4] != (uint8_t)(crc & 0xFFu) || raw[n - 3] != (uint8_t)((crc >> 8) & 0xFFu) ||
      raw[n - 2] != (uint8_t)((crc >> 16) & 0xFFu) || raw[n - 1] != (uint8_t)((crc >> 24) & 0xFFu))
    return VEST_FRAME_CRC;
  if (version)
    *version = raw[0];
  if (raw[0] != VEST_PROTOCOL_VERSION)
    return VEST_FRAME_VERSION;
  if (n != (int)VEST_RAW_SIZE)
    return VEST_FRAME_LENGTH;
  if ((raw[1] != VEST_TYPE_COMMAND && raw[1] != VEST_TYPE_STATUS) || (raw[3] & 0xF0u) != 0u)
    return VEST_FRAME_FIELD;
  p->type = raw[1];
  p->seq = raw[2];
  p->motors = raw[3];
  for (i = 0; i < VEST_NUM_MOTORS; ++i)
    p->intensity[i] = raw[4 + i];
  p->ttl_ms = (uint16_t)(raw[8] | ((uint16_t)raw[9] << 8));
  return VEST_FRAME_OK;
}

/* Checks one whole wire packet as vest_encode writes it (VEST_PACKET_SIZE bytes, both
 * delimiters); returns 1 and fills p when it is valid. */
static inline int vest_decode(const uint8_t* in, vest_packet_t* p)
{
  uint8_t i;
  if (in[0] != VEST_DELIMITER || in[VEST_PACKET_SIZE - 1u] != VEST_DELIMITER)
    return 0;
  for (i = 1u; i < VEST_PACKET_SIZE - 1u; ++i)
    if (in[i] == VEST_DELIMITER)
      return 0;
  return vest_decode_frame(in + 1, (uint8_t)VEST_COBS_SIZE, p, 0) == VEST_FRAME_OK;
}

/* Effective duty of motor i of a packet. */
static inline uint8_t vest_motor_duty(const vest_packet_t* p, uint8_t i)
{
  return ((p->motors >> i) & 1u) ? p->intensity[i] : (uint8_t)0u;
}

/* ---- Streaming parser: feed bytes one at a time. ---- */
typedef struct
{
  uint8_t buf[VEST_MAX_FRAME];
  uint8_t len;
  uint8_t overflow;           /* the current frame outgrew buf: dropped at the next delimiter */
  uint8_t peer_version;       /* VERSION of the last CRC-valid frame of another version */
  uint16_t packets;           /* valid packets (wraps) */
  uint16_t rejected;          /* non-empty frames that failed a check (wraps) */
  uint16_t skipped;           /* bytes in rejected frames (wraps) */
  uint16_t version_mismatch;  /* CRC-valid frames of another protocol version (wraps) */
} vest_parser_t;

static inline void vest_parser_init(vest_parser_t* ps)
{
  memset(ps, 0, sizeof(*ps));
}

/* Feeds one byte. Returns 1 when it completed a valid packet (copied to *out), else 0. */
static inline int vest_parser_feed(vest_parser_t* ps, uint8_t byte, vest_packet_t* out)
{
  int r;
  uint8_t version = 0u, n;
  if (byte != VEST_DELIMITER)
  {
    if (ps->len < VEST_MAX_FRAME)
      ps->buf[ps->len++] = byte;
    else
    {
      ps->overflow = 1u;
      ps->skipped++;
    }
    return 0;
  }
  n = ps->len;
  ps->len = 0u;
  if (ps->overflow)
  {
    ps->overflow = 0u;
    ps->rejected++;
    ps->skipped = (uint16_t)(ps->skipped + n);
    return 0;
  }
  if (n == 0u)
    return 0; /* two delimiters in a row: between packets */
  r = vest_decode_frame(ps->buf, n, out, &version);
  if (r == VEST_FRAME_OK)
  {
    ps->packets++;
    return 1;
  }
  if (r == VEST_FRAME_VERSION)
  {
    ps->version_mismatch++;
    ps->peer_version = version;
  }
  ps->rejected++;
  ps->skipped = (uint16_t)(ps->skipped + n);
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
  uint16_t hold_ms;              /* the last COMMAND drives until last_command_ms + hold_ms */
  uint16_t timeouts;             /* watchdog trips (wraps) */
  uint16_t expiries;             /* commands that ran out of TTL (wraps) */
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

/* Fills a STATUS with what the outputs do now. */
static inline void vest_firmware_status(const vest_firmware_t* fw, vest_packet_t* status)
{
  uint8_t i;
  status->type = VEST_TYPE_STATUS;
  status->seq = fw->last_seq;
  status->motors = fw->motors;
  for (i = 0; i < VEST_NUM_MOTORS; ++i)
    status->intensity[i] = fw->duty[i];
  status->ttl_ms = 0u;
}

/* Feeds one received byte. Returns VEST_FEED_APPLIED when a valid COMMAND was applied, and
 * VEST_FEED_VERSION_REPLY when a CRC-valid frame of another protocol version ended (counted in
 * parser.version_mismatch; nothing applied); in both cases *status holds the STATUS packet to
 * send back. STATUS packets and anything invalid are ignored (VEST_FEED_NONE). */
static inline int vest_firmware_feed(vest_firmware_t* fw, uint8_t byte, uint32_t now_ms,
                                     vest_packet_t* status)
{
  vest_packet_t p;
  uint8_t i;
  const uint16_t mismatches = fw->parser.version_mismatch;
  if (!vest_parser_feed(&fw->parser, byte, &p))
  {
    if (fw->parser.version_mismatch == mismatches)
      return VEST_FEED_NONE;
    vest_firmware_status(fw, status); /* our version in the reply: the peer can report it */
    return VEST_FEED_VERSION_REPLY;
  }
  if (p.type != VEST_TYPE_COMMAND)
    return VEST_FEED_NONE;
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
  fw->hold_ms = p.ttl_ms < VEST_WATCHDOG_MS ? p.ttl_ms : (uint16_t)VEST_WATCHDOG_MS;
  vest_firmware_status(fw, status);
  return VEST_FEED_APPLIED;
}

/* TTL and watchdog; call every loop. Returns VEST_TICK_EXPIRED / VEST_TICK_WATCHDOG when it
 * just switched the motors off (the command's TTL ran out / no COMMAND for VEST_WATCHDOG_MS),
 * else VEST_TICK_NONE. Unsigned subtraction keeps it right across the millis() wrap (49.7 days). */
static inline int vest_firmware_tick(vest_firmware_t* fw, uint32_t now_ms)
{
  if (fw->have_command && (uint32_t)(now_ms - fw->last_command_ms) > fw->hold_ms)
  {
    vest_firmware_all_off(fw);
    fw->have_command = 0u;
    if (fw->hold_ms < VEST_WATCHDOG_MS)
    {
      fw->expiries++;
      return VEST_TICK_EXPIRED;
    }
    fw->timeouts++;
    return VEST_TICK_WATCHDOG;
  }
  return VEST_TICK_NONE;
}

#ifdef __cplusplus
} /* extern "C" */
#endif

#endif /* ASSISTIVE_TACTILE_VEST_PROTOCOL_H */
