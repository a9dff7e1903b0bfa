/*
 * vest_protocol.h -- THE definition of the serial protocol between the PC (vest bridge) and the
 * tactile vest's microcontroller. Plain C99 / C++, header-only, no allocation, no OS calls: the
 * same file is compiled into the ROS bridge (assistive_tactile_core), the simulated vest and the
 * Arduino sketch (firmware/vest/vest.ino includes it through the symlink
 * firmware/vest/vest_protocol.h). Change it here and both sides change.
 *
 * Version history:
 *   1  SYNC 0xA5 + CRC-8: let noise through as false COMMANDs. Not spoken.
 *   2  COBS framing + CRC-32C; COMMAND / STATUS (14 bytes) with TTL_MS.
 *   3  + RANGE (forward ultrasonic ranger, issue 20) and BUTTONS (the wearer's push buttons,
 *      issue 24), vest -> PC. COMMAND / STATUS as in version 2.
 *   4  (issue 33, cues for walking) COMMAND / STATUS grow by four bytes: the PULSE
 *      PATTERN (PATTERN_ID, ON_10MS, OFF_10MS, COUNT), 18 bytes. The VEST times the pulses
 *      itself (vest_firmware_*), so USB / radio jitter and lost packets never change how long a
 *      pulse lasts or how many pulses are felt; the PC only says which pattern plays. RANGE and
 *      BUTTONS unchanged (VERSION 4, the same bytes).
 *   5  (this one; issue 33, the body's heading) + IMU (the vest's gyro and accelerometer on the
 *      torso, vest -> PC, 50 Hz): the torso's turns, which a head-mounted camera cannot give (the
 *      head scans +-8 deg while the body walks straight). COMMAND / STATUS / RANGE / BUTTONS as
 *      in version 4 (the same bytes, VERSION 5).
 *
 * Older peers (VEST_PROTOCOL_MIN_VERSION = 2):
 *   - A version-4 VEST (pulse patterns, no IMU) is DRIVEN in version 4: it answers the bridge's
 *     first version-5 COMMAND with a version-4 STATUS (nothing applied), and from then on the
 *     bridge sends version-4 COMMANDs (the same bytes), which it obeys. It sends no IMU; the cue
 *     logic then takes the body's turns from the head, as before version 5 (diagnostics WARN:
 *     "no IMU, reflash"). Every 2 s such a bridge also sends the same state once in version 5:
 *     a vest reflashed on a link that stayed open applies it (the same pattern: nothing
 *     restarts) and answers in version 5; the version-4 one answers it with a STATUS and
 *     ignores it.
 *   - An old VEST (version 2 or 3) is REFUSED by the bridge: it gets no motor-driving COMMAND at
 *     all (the bridge sends only version-4 / 5 COMMANDs, which an old vest counts and answers with a
 *     STATUS of its own version), its motors stay off (its 500 ms watchdog ends whatever an
 *     earlier bridge left on), and the bridge reports ERROR naming the vest's version
 *     ("reflash"). The wearer feels silence, which this protocol defines as "stop, use the
 *     cane". Why not drive it with pulses timed by the PC (steady duties switched per pulse)?
 *     The instruction now lives in the pulses' number and length (veer = two 150 ms pulses,
 *     stop-and-turn = one 800 ms buzz, walk on = one 100 ms tick, unsure = three 100 ms
 *     pulses): a pulse rendered from 20 Hz re-sends is quantised to 50 ms, and one lost or late
 *     packet (the seed's radio link) adds, drops or stretches a pulse, i.e. says something else.
 *     Silence cannot be misread; a wrong pattern can. A reflash takes a minute
 *     (firmware/build_firmware.sh + avrdude).
 *   - An old BRIDGE (version 2, 3 or 4) is still obeyed by this vest: a version-2 / 3 COMMAND
 *     has no pattern bytes and is rendered steady (the old meaning), a version-4 one is as
 *     ours; each is answered with a STATUS in its version; RANGE / BUTTONS go out in its version
 *     when it is 3 or 4 (the layout is the same); IMU only to a version-5 bridge.
 *   The receivers decode versions 2..5 (so the bridge learns an old vest's version from its
 *   STATUS); other versions are rejected and counted.
 *
 * COMMAND / STATUS (versions 4 / 5: 18 bytes before framing; versions 2 / 3: bytes 0..9 + CRC, 14):
 *
 *   byte 0    VERSION   5 (2 / 3 / 4 from and to an old bridge or vest only)
 *   byte 1    TYPE      0x01 = COMMAND (PC -> vest), 0x02 = STATUS (vest -> PC)
 *   byte 2    SEQ       sequence number, +1 per packet sent (wraps at 255); a STATUS echoes the
 *                       SEQ of the last COMMAND the vest accepted
 *   byte 3    MOTORS    bit i set = motor i on (bit 0 left shoulder, 1 right shoulder,
 *                       2 left waist, 3 right waist); bits 4..7 must be 0.
 *                       COMMAND: the motors the pattern drives. STATUS: the motors on NOW.
 *   byte 4-7  I0..I3    PWM duty of motor i (0..255), used only when its bit is set.
 *                       COMMAND: the duty while the pattern is on. STATUS: the duty NOW (0 in a
 *                       pattern's gap).
 *   byte 8-9  TTL_MS    uint16, low byte first. COMMAND: the vest drives this command for at
 *                       most TTL_MS ms after it received the packet, then switches every motor
 *                       off by itself (capped by VEST_WATCHDOG_MS); the PC sets it from the cue's
 *                       stamps, so a cue ends on time even when the PC stalls. STATUS: 0.
 *   byte 10   PATTERN_ID  which pattern (version 4 on). A COMMAND whose pattern (ID, ON, OFF, COUNT)
 *                       equals the running one CONTINUES its phase (the PC re-sends at 20 Hz and
 *                       the cue logic repeats a pattern it holds); any other starts it at 0 ms.
 *                       The phase survives a TTL / watchdog cut: the same pattern coming back
 *                       continues where its clock stands (a burst is never replayed).
 *   byte 11   ON_10MS   pulse length in 10 ms (10..2550 ms); 0 = STEADY (driven all the time,
 *                       OFF_10MS and COUNT must then be 0)
 *   byte 12   OFF_10MS  gap between pulses in 10 ms
 *   byte 13   COUNT     pulses, then off until a new pattern; 0 = pulse for as long as the
 *                       COMMANDs last. The motors are driven t ms after the pattern started
 *                       iff vest_pattern_on(pattern, t), and only while TTL and watchdog allow.
 *                       STATUS: bytes 10..13 = the pattern the vest is playing.
 *   byte 14-17 CRC      CRC-32C (Castagnoli: poly 0x1EDC6F41 reflected, init and final xor
 *                       0xFFFFFFFF; check value 0xE3069283) over bytes 0..13, low byte first.
 *                       (CRC-16/CCITT-FALSE let 1 damaged frame through per ~3e7 random
 *                       corruptions in tactile_benchmark; 32 bits make that 65536 times rarer.)
 *
 * RANGE (vest -> PC, 11 bytes before framing; one per ping, 20 Hz, median of the last 3 pings):
 *
 *   byte 0    VERSION   5 (3 / 4 to a version-3 / 4 bridge)
 *   byte 1    TYPE      0x03
 *   byte 2    SEQ       +1 per RANGE packet (the PC counts lost ones)
 *   byte 3    STATUS    0 = OK (RANGE_MM holds the median), 1 = NO_ECHO (fewer than 2 of the last
 *                       3 pings came back within VEST_RANGE_MAX_MM), 2 = SENSOR_MISSING (2 or more
 *                       of them never raised the echo line: unplugged / dead sensor); others illegal
 *   byte 4-5  RANGE_MM  uint16, low byte first: distance in mm (speed of sound 343 m/s); 0 unless OK
 *   byte 6    ECHOES    pings of the last 3 that returned an echo (0..3; OK needs >= 2)
 *   byte 7-10 CRC       CRC-32C over bytes 0..6
 *
 * BUTTONS (vest -> PC, 12 bytes before framing; on every press event and change of HELD, and once
 * a second as a heartbeat, so a lost packet is healed by the next one):
 *
 *   byte 0    VERSION   5 (3 / 4 to a version-3 / 4 bridge)
 *   byte 1    TYPE      0x04
 *   byte 2    SEQ       +1 per BUTTONS packet
 *   byte 3    HELD      debounced state now: bit 0 = button A down, bit 1 = B; bits 2..7 must be 0
 *   byte 4-7  COUNTS    SHORT_A, LONG_A, SHORT_B, LONG_B: presses since power-up (wrap at 255);
 *                       the PC reports the difference to the previous packet's counts. A press is
 *                       LONG when held VEST_LONG_PRESS_MS (reported then, while still held), SHORT
 *                       when released before; the inputs are debounced over VEST_DEBOUNCE_MS.
 *   byte 8-11 CRC       CRC-32C over bytes 0..7
 *
 * IMU (vest -> PC, version 5, 23 bytes before framing; every VEST_IMU_PERIOD_MS = 20 ms, to a
 * version-5 bridge only): the MEAN of the samples read in the 20 ms before T_MS (one every
 * VEST_IMU_SAMPLE_MS), so the PC integrates the turn exactly (mean rate x window) and nothing
 * between the samples aliases. Axes: the sensor's, as mounted on the torso (REP-103 when it is
 * mounted x forward, y left, z up); the PC takes the vertical from the accelerometer, so the
 * mounting's tilt does not matter to the body's yaw rate.
 *
 *   byte 0    VERSION   5
 *   byte 1    TYPE      0x05
 *   byte 2    SEQ       +1 per IMU packet (the PC counts lost ones)
 *   byte 3    STATUS    0 = OK, 1 = SENSOR_MISSING (no sample of the window could be read: I2C
 *                       error or wrong WHO_AM_I: unplugged / dead sensor; or the 50 ms a woken
 *                       sensor's gyro takes to settle); others illegal
 *   byte 4    SAMPLES   samples averaged (1..255 when OK, 0 when missing)
 *   byte 5-6  T_MS      uint16, low byte first: the vest's millisecond clock (low 16 bits) at the
 *                       window's end; the window began at the previous packet's T_MS
 *   byte 7-12 GYRO      int16 x, y, z, low byte first: mean angular rate in mrad/s (+-32.767
 *                       rad/s, saturating); 0 when missing
 *   byte 13-18 ACCEL    int16 x, y, z: mean specific force in mm/s^2 (+-32.767 m/s^2 = 3.3 g,
 *                       saturating); 0 when missing
 *   byte 19-22 CRC      CRC-32C over bytes 0..18
 *
 * Framing: COBS (Consistent Overhead Byte Stuffing). The 18 bytes are COBS-encoded (19 bytes, no
 * 0x00 inside) and sent between two 0x00 delimiters: 21 bytes on the wire (3.65 ms at 57600
 * baud; version 2 / 3: 17 bytes),
 *
 *   0x00  COBS(packet)  0x00
 *
 * A receiver collects the bytes between delimiters into a frame and accepts it only when the COBS
 * structure is valid, the CRC matches, VERSION is one we speak, TYPE is known in that version, the
 * decoded length is exactly that TYPE's in that VERSION and the fields are legal. Since a frame
 * starts only at a delimiter, a packet is never read at a shifted offset (the SYNC scan of
 * version 1 could); garbage, a truncated or a shifted packet cost that frame only, and the next
 * delimiter resynchronises. The leading delimiter ends any garbage before the packet, so the
 * packet after a burst of noise still arrives. The CRC is checked before VERSION, so a counted
 * version mismatch is a real peer of another version, not noise; the CRC sits at the end of
 * every version's frame for that reason.
 *
 * Motor i is driven at  (MOTORS >> i) & 1 ? Ii : 0  while the pattern is on, else 0.
 * A COMMAND is the complete desired state (not a delta), so a lost packet is healed by the next
 * one (same pattern: same phase). The PC re-sends it at a fixed rate (default 20 Hz). The vest
 * switches every motor off when the last COMMAND's TTL ran out or no valid COMMAND arrived for
 * VEST_WATCHDOG_MS (whichever comes first), and answers every accepted COMMAND with a STATUS
 * carrying what the motors do now and the pattern it plays (link proof and diagnostics).
 */
#ifndef ASSISTIVE_TACTILE_VEST_PROTOCOL_H
#define ASSISTIVE_TACTILE_VEST_PROTOCOL_H

#include <stdint.h>
#include <string.h>

#ifdef __cplusplus
extern "C" {
#endif

#define VEST_PROTOCOL_VERSION 5u
#define VEST_PROTOCOL_MIN_VERSION 2u  /* oldest version decoded (COMMAND / STATUS only) */
#define VEST_PATTERN_VERSION 4u       /* first version with the pattern bytes */
#define VEST_IMU_VERSION 5u           /* first version with the IMU packet */
#define VEST_DELIMITER 0x00u
#define VEST_TYPE_COMMAND 0x01u
#define VEST_TYPE_STATUS 0x02u
#define VEST_TYPE_RANGE 0x03u    /* version 3 on */
#define VEST_TYPE_BUTTONS 0x04u  /* version 3 on */
#define VEST_TYPE_IMU 0x05u      /* version 5 on */
#define VEST_CRC_SIZE 4u
#define VEST_RAW_SIZE 18u                       /* VERSION .. CRC, before COBS (versions 4, 5) */
#define VEST_COBS_SIZE (VEST_RAW_SIZE + 1u)     /* COBS adds one byte to frames under 254 bytes */
#define VEST_PACKET_SIZE (VEST_COBS_SIZE + 2u)  /* on the wire, with both delimiters: 21 */
#define VEST_RAW_SIZE_V3 14u                    /* COMMAND / STATUS of versions 2 and 3 */
#define VEST_PACKET_SIZE_V3 (VEST_RAW_SIZE_V3 + 3u)  /* 17 on the wire */
#define VEST_RANGE_RAW_SIZE 11u
#define VEST_RANGE_PACKET_SIZE (VEST_RANGE_RAW_SIZE + 3u)      /* 14 on the wire */
#define VEST_BUTTONS_RAW_SIZE 12u
#define VEST_BUTTONS_PACKET_SIZE (VEST_BUTTONS_RAW_SIZE + 3u)  /* 15 on the wire */
#define VEST_IMU_RAW_SIZE 23u
#define VEST_IMU_PACKET_SIZE (VEST_IMU_RAW_SIZE + 3u)  /* 26 on the wire */
#define VEST_MAX_PACKET_SIZE VEST_IMU_PACKET_SIZE      /* the longest packet: an output buffer's size */
#define VEST_MAX_FRAME 32u  /* longest frame a receiver buffers; longer = garbage, dropped */

/* RANGE STATUS */
#define VEST_RANGE_OK 0u
#define VEST_RANGE_NO_ECHO 1u
#define VEST_RANGE_SENSOR_MISSING 2u
/* One ping (vest_ranger_ping's input) */
#define VEST_PING_ECHO 0u
#define VEST_PING_NO_ECHO 1u   /* the echo line rose but no echo came back in time */
#define VEST_PING_MISSING 2u   /* the echo line never rose: no sensor answering */
#define VEST_RANGE_MAX_MM 4000u       /* HC-SR04 class: 4 m; a longer echo counts as none */
#define VEST_ECHO_TIMEOUT_US 30000ul  /* no falling edge this long after the rise: no echo */
#define VEST_PING_PERIOD_MS 50u       /* 20 Hz; the HC-SR04 needs >= 40 ms between pings */
/* Buttons */
#define VEST_NUM_BUTTONS 2u
#define VEST_BUTTON_A 0u
#define VEST_BUTTON_B 1u
#define VEST_DEBOUNCE_MS 30u
#define VEST_LONG_PRESS_MS 1000u
#define VEST_BUTTONS_PERIOD_MS 1000u  /* heartbeat BUTTONS packet */
#define VEST_PRESS_NONE 0
#define VEST_PRESS_SHORT 1
#define VEST_PRESS_LONG 2
/* IMU */
#define VEST_IMU_OK 0u
#define VEST_IMU_SENSOR_MISSING 1u
#define VEST_IMU_PERIOD_MS 20u  /* one IMU packet per 20 ms: 50 Hz, 1.3 kB/s of 5.76 at 57600 baud */
#define VEST_IMU_SAMPLE_MS 5u   /* the sketch reads the sensor every 5 ms (4 samples a packet) */
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
#define VEST_TICK_PULSE 3     /* the pattern switched the outputs (a pulse began or ended) */

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
#define VEST_FRAME_FIELD 6    /* unknown TYPE (in this VERSION) or an illegal field */
#define VEST_FRAME_OTHER_TYPE 7  /* valid, but RANGE / BUTTONS / IMU where a COMMAND / STATUS was asked */

/* A pulse pattern (protocol version 4, the walking cues of issue 33): the motors of a COMMAND are
 * driven in pulses the vest times itself, so USB jitter never changes what the wearer feels.
 * ID names one pattern: a COMMAND with the same pattern as the running one (the same ID and the
 * same timing: vest_pattern_equal) continues its phase (the PC re-sends at 20 Hz), a new ID
 * restarts it at 0. ON_10MS 0 = steady (driven all the time; OFF_10MS and COUNT 0). */
typedef struct
{
  uint8_t id;        /* changes when a new pattern starts */
  uint8_t on_10ms;   /* pulse length, 10 ms units; 0 = steady */
  uint8_t off_10ms;  /* gap between pulses, 10 ms units */
  uint8_t count;     /* pulses, then off; 0 = pulse for as long as the COMMAND lasts */
} vest_pattern_t;

/* 1 when a pattern drives its motors t_ms after it started, else 0. */
static inline int vest_pattern_on(const vest_pattern_t* p, uint32_t t_ms)
{
  uint32_t period, k;
  if (p->on_10ms == 0u)
    return 1;
  period = 10ul * ((uint32_t)p->on_10ms + (uint32_t)p->off_10ms);
  k = t_ms / period;
  if (p->count != 0u && k >= (uint32_t)p->count)
    return 0;
  return (t_ms - k * period) < 10ul * (uint32_t)p->on_10ms ? 1 : 0;
}

#define VEST_NEVER 0xFFFFFFFFul  /* "no such time" in the pattern helpers below */

/* 1 when a and b are the same pattern (all four fields): a COMMAND carrying the running pattern
 * continues it, any other pattern restarts. */
static inline int vest_pattern_equal(const vest_pattern_t* a, const vest_pattern_t* b)
{
  return a->id == b->id && a->on_10ms == b->on_10ms && a->off_10ms == b->off_10ms && a->count == b->count;
}

/* ms after its start at which a pattern's last pulse has ended (the pattern is over);
 * VEST_NEVER for a steady pattern or one that pulses without a count. */
static inline uint32_t vest_pattern_length_ms(const vest_pattern_t* p)
{
  if (p->on_10ms == 0u || p->count == 0u)
    return VEST_NEVER;
  return 10ul * (((uint32_t)p->count - 1ul) * ((uint32_t)p->on_10ms + (uint32_t)p->off_10ms) + (uint32_t)p->on_10ms);
}

/* ms from t_ms (after the pattern started) until vest_pattern_on() may change next (a pulse
 * begins or ends; an edge that changes nothing, e.g. between pulses without a gap, may be
 * named too); VEST_NEVER when it never changes again. */
static inline uint32_t vest_pattern_next_edge_ms(const vest_pattern_t* p, uint32_t t_ms)
{
  uint32_t period, k, phase, on_ms;
  if (p->on_10ms == 0u)
    return VEST_NEVER;
  on_ms = 10ul * (uint32_t)p->on_10ms;
  period = 10ul * ((uint32_t)p->on_10ms + (uint32_t)p->off_10ms);
  k = t_ms / period;
  if (p->count != 0u && k >= (uint32_t)p->count)
    return VEST_NEVER;
  phase = t_ms - k * period;
  if (phase < on_ms)
    return on_ms - phase;  /* this pulse ends */
  if (p->count != 0u && k + 1u >= (uint32_t)p->count)
    return VEST_NEVER;     /* that was the last pulse */
  return period - phase;   /* the next pulse begins */
}

/* COMMAND / STATUS. */
typedef struct
{
  uint8_t type;
  uint8_t seq;
  uint8_t motors;                       /* bit mask, bits 0..3 */
  uint8_t intensity[VEST_NUM_MOTORS];   /* 0..255 */
  uint16_t ttl_ms;                      /* COMMAND: drive at most this long after receipt */
  vest_pattern_t pattern;               /* version 4; versions 2 / 3: all 0 (steady) */
} vest_packet_t;

/* RANGE */
typedef struct
{
  uint8_t seq;
  uint8_t status;     /* VEST_RANGE_* */
  uint16_t range_mm;  /* median of the last 3 pings when status is OK, else 0 */
  uint8_t echoes;     /* pings of the last 3 with an echo */
} vest_range_t;

/* BUTTONS */
typedef struct
{
  uint8_t seq;
  uint8_t held;        /* bit 0 = A down, bit 1 = B down */
  uint8_t short_a, long_a, short_b, long_b;  /* press counters (wrap) */
} vest_buttons_t;

/* IMU (version 5) */
typedef struct
{
  uint8_t seq;
  uint8_t status;      /* VEST_IMU_* */
  uint8_t samples;     /* samples averaged (0 when missing) */
  uint16_t t_ms;       /* the vest's millis() at the window's end, low 16 bits */
  int16_t gyro[3];     /* mean angular rate, mrad/s */
  int16_t accel[3];    /* mean specific force, mm/s^2 */
} vest_imu_t;

/* Any valid packet. */
typedef struct
{
  uint8_t version;  /* VERSION byte (VEST_PROTOCOL_MIN_VERSION .. VEST_PROTOCOL_VERSION) */
  uint8_t type;     /* VEST_TYPE_* */
  vest_packet_t packet;    /* COMMAND, STATUS */
  vest_range_t range;      /* RANGE */
  vest_buttons_t buttons;  /* BUTTONS */
  vest_imu_t imu;          /* IMU */
} vest_message_t;

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

/* Raw size (before COBS, CRC included) of a COMMAND / STATUS in `version`. */
static inline uint8_t vest_command_raw_size(uint8_t version)
{
  return version >= VEST_PATTERN_VERSION ? (uint8_t)VEST_RAW_SIZE : (uint8_t)VEST_RAW_SIZE_V3;
}

/* Bytes on the wire of a COMMAND / STATUS in `version` (VEST_PACKET_SIZE in ours). */
static inline uint8_t vest_command_packet_size(uint8_t version)
{
  return (uint8_t)(vest_command_raw_size(version) + 3u);
}

/* 16-bit fields, low byte first (TTL_MS, RANGE_MM, T_MS; the IMU's int16 readings). */
static inline void vest_put_u16(uint8_t* at, uint16_t v)
{
  at[0] = (uint8_t)(v & 0xFFu);
  at[1] = (uint8_t)(v >> 8);
}

static inline uint16_t vest_get_u16(const uint8_t* at)
{
  return (uint16_t)(at[0] | ((uint16_t)at[1] << 8));
}

static inline void vest_put_i16(uint8_t* at, int16_t v)
{
  vest_put_u16(at, (uint16_t)v);
}

static inline int16_t vest_get_i16(const uint8_t* at)
{
  return (int16_t)vest_get_u16(at);
}

/* Writes a COMMAND / STATUS (delimiter, COBS frame, delimiter) with VERSION `version` to out
 * (VEST_PACKET_SIZE bytes room) and returns the bytes written: VEST_PACKET_SIZE in version 4,
 * VEST_PACKET_SIZE_V3 in versions 2 / 3 (no pattern bytes: an old peer's COMMAND is steady). A
 * steady pattern (ON_10MS 0) is written with OFF_10MS and COUNT 0, as the receiver demands. */
static inline uint8_t vest_encode_version(const vest_packet_t* p, uint8_t version, uint8_t* out)
{
  uint8_t raw[VEST_RAW_SIZE - VEST_CRC_SIZE];
  uint8_t i;
  const uint8_t steady = p->pattern.on_10ms == 0u;
  raw[0] = version;
  raw[1] = p->type;
  raw[2] = p->seq;
  raw[3] = (uint8_t)(p->motors & 0x0Fu);
  for (i = 0; i < VEST_NUM_MOTORS; ++i)
    raw[4 + i] = p->intensity[i];
  vest_put_u16(raw + 8, p->ttl_ms);
  raw[10] = p->pattern.id;
  raw[11] = p->pattern.on_10ms;
  raw[12] = steady ? (uint8_t)0u : p->pattern.off_10ms;
  raw[13] = steady ? (uint8_t)0u : p->pattern.count;
  return vest_frame(raw, (uint8_t)(vest_command_raw_size(version) - VEST_CRC_SIZE), out);
}

/* Writes VEST_PACKET_SIZE bytes; VERSION is ours. */
static inline void vest_encode(const vest_packet_t* p, uint8_t* out)
{
  vest_encode_version(p, (uint8_t)VEST_PROTOCOL_VERSION, out);
}

/* Writes VEST_RANGE_PACKET_SIZE bytes with VERSION `version` (3, 4 or 5: the same layout). */
static inline void vest_encode_range_version(const vest_range_t* r, uint8_t version, uint8_t* out)
{
  uint8_t raw[VEST_RANGE_RAW_SIZE - VEST_CRC_SIZE];
  raw[0] = version;
  raw[1] = (uint8_t)VEST_TYPE_RANGE;
  raw[2] = r->seq;
  raw[3] = r->status;
  vest_put_u16(raw + 4, r->range_mm);
  raw[6] = r->echoes;
  vest_frame(raw, (uint8_t)(VEST_RANGE_RAW_SIZE - VEST_CRC_SIZE), out);
}

/* Writes VEST_RANGE_PACKET_SIZE bytes; VERSION is ours. */
static inline void vest_encode_range(const vest_range_t* r, uint8_t* out)
{
  vest_encode_range_version(r, (uint8_t)VEST_PROTOCOL_VERSION, out);
}

/* Writes VEST_BUTTONS_PACKET_SIZE bytes with VERSION `version` (3, 4 or 5: the same layout). */
static inline void vest_encode_buttons_version(const vest_buttons_t* b, uint8_t version, uint8_t* out)
{
  uint8_t raw[VEST_BUTTONS_RAW_SIZE - VEST_CRC_SIZE];
  raw[0] = version;
  raw[1] = (uint8_t)VEST_TYPE_BUTTONS;
  raw[2] = b->seq;
  raw[3] = b->held;
  raw[4] = b->short_a;
  raw[5] = b->long_a;
  raw[6] = b->short_b;
  raw[7] = b->long_b;
  vest_frame(raw, (uint8_t)(VEST_BUTTONS_RAW_SIZE - VEST_CRC_SIZE), out);
}

/* Writes VEST_BUTTONS_PACKET_SIZE bytes; VERSION is ours. */
static inline void vest_encode_buttons(const vest_buttons_t* b, uint8_t* out)
{
  vest_encode_buttons_version(b, (uint8_t)VEST_PROTOCOL_VERSION, out);
}

/* Writes VEST_IMU_PACKET_SIZE bytes with VERSION `version` (5; the argument keeps the sketch's
 * sensor senders alike). */
static inline void vest_encode_imu_version(const vest_imu_t* u, uint8_t version, uint8_t* out)
{
  uint8_t raw[VEST_IMU_RAW_SIZE - VEST_CRC_SIZE];
  uint8_t i;
  raw[0] = version;
  raw[1] = (uint8_t)VEST_TYPE_IMU;
  raw[2] = u->seq;
  raw[3] = u->status;
  raw[4] = u->samples;
  vest_put_u16(raw + 5, u->t_ms);
  for (i = 0; i < 3u; ++i)
  {
    vest_put_i16(raw + 7 + 2 * i, u->gyro[i]);
    vest_put_i16(raw + 13 + 2 * i, u->accel[i]);
  }
  vest_frame(raw, (uint8_t)(VEST_IMU_RAW_SIZE - VEST_CRC_SIZE), out);
}

/* Writes VEST_IMU_PACKET_SIZE bytes; VERSION is ours. */
static inline void vest_encode_imu(const vest_imu_t* u, uint8_t* out)
{
  vest_encode_imu_version(u, (uint8_t)VEST_PROTOCOL_VERSION, out);
}

/* Checks one frame (the bytes between two delimiters). Returns VEST_FRAME_OK and fills m when it
 * is a valid packet of a version we speak; else the reason. *version gets the VERSION byte of a
 * CRC-valid frame (for mismatch reports); it may be NULL. */
static inline int vest_decode_message(const uint8_t* frame, uint8_t len, vest_message_t* m, uint8_t* version)
{
  uint8_t raw[VEST_MAX_FRAME];
  uint8_t i, want;
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
  if (raw[0] < VEST_PROTOCOL_MIN_VERSION || raw[0] > VEST_PROTOCOL_VERSION)
    return VEST_FRAME_VERSION;
  if (n < 2)
    return VEST_FRAME_LENGTH;
  /* TYPE known in this VERSION, then its length, then its fields. */
  if (raw[1] == VEST_TYPE_COMMAND || raw[1] == VEST_TYPE_STATUS)
    want = vest_command_raw_size(raw[0]);
  else if (raw[1] == VEST_TYPE_RANGE && raw[0] >= 3u)
    want = (uint8_t)VEST_RANGE_RAW_SIZE;
  else if (raw[1] == VEST_TYPE_BUTTONS && raw[0] >= 3u)
    want = (uint8_t)VEST_BUTTONS_RAW_SIZE;
  else if (raw[1] == VEST_TYPE_IMU && raw[0] >= VEST_IMU_VERSION)
    want = (uint8_t)VEST_IMU_RAW_SIZE;
  else
    return VEST_FRAME_FIELD;
  if (n != (int)want)
    return VEST_FRAME_LENGTH;
  memset(m, 0, sizeof(*m));
  m->version = raw[0];
  m->type = raw[1];
  if (raw[1] == VEST_TYPE_RANGE)
  {
    m->range.seq = raw[2];
    m->range.status = raw[3];
    m->range.range_mm = vest_get_u16(raw + 4);
    m->range.echoes = raw[6];
    if (m->range.status > VEST_RANGE_SENSOR_MISSING || m->range.echoes > 3u ||
        (m->range.status == VEST_RANGE_OK && m->range.echoes < 2u) ||
        (m->range.status != VEST_RANGE_OK && m->range.range_mm != 0u))
      return VEST_FRAME_FIELD;
    return VEST_FRAME_OK;
  }
  if (raw[1] == VEST_TYPE_IMU)
  {
    m->imu.seq = raw[2];
    m->imu.status = raw[3];
    m->imu.samples = raw[4];
    m->imu.t_ms = vest_get_u16(raw + 5);
    for (i = 0; i < 3u; ++i)
    {
      m->imu.gyro[i] = vest_get_i16(raw + 7 + 2 * i);
      m->imu.accel[i] = vest_get_i16(raw + 13 + 2 * i);
    }
    if (m->imu.status > VEST_IMU_SENSOR_MISSING || (m->imu.status == VEST_IMU_OK && m->imu.samples == 0u))
      return VEST_FRAME_FIELD;
    if (m->imu.status == VEST_IMU_SENSOR_MISSING)
      for (i = 7; i < 19u; ++i)
        if (raw[4] != 0u || raw[i] != 0u)
          return VEST_FRAME_FIELD;  /* a missing sensor measured nothing */
    return VEST_FRAME_OK;
  }
  if (raw[1] == VEST_TYPE_BUTTONS)
  {
    if ((raw[3] & 0xFCu) != 0u)
      return VEST_FRAME_FIELD;
    m->buttons.seq = raw[2];
    m->buttons.held = raw[3];
    m->buttons.short_a = raw[4];
    m->buttons.long_a = raw[5];
    m->buttons.short_b = raw[6];
    m->buttons.long_b = raw[7];
    return VEST_FRAME_OK;
  }
  if ((raw[3] & 0xF0u) != 0u)
    return VEST_FRAME_FIELD;
  m->packet.type = raw[1];
  m->packet.seq = raw[2];
  m->packet.motors = raw[3];
  for (i = 0; i < VEST_NUM_MOTORS; ++i)
    m->packet.intensity[i] = raw[4 + i];
  m->packet.ttl_ms = vest_get_u16(raw + 8);
  if (raw[0] >= VEST_PATTERN_VERSION)
  {
    /* a steady pattern carries no timing */
    if (raw[11] == 0u && (raw[12] != 0u || raw[13] != 0u))
      return VEST_FRAME_FIELD;
    m->packet.pattern.id = raw[10];
    m->packet.pattern.on_10ms = raw[11];
    m->packet.pattern.off_10ms = raw[12];
    m->packet.pattern.count = raw[13];
  }
  return VEST_FRAME_OK;
}

/* vest_decode_message for COMMAND / STATUS only (a valid RANGE / BUTTONS / IMU: VEST_FRAME_OTHER_TYPE). */
static inline int vest_decode_frame(const uint8_t* frame, uint8_t len, vest_packet_t* p, uint8_t* version)
{
  vest_message_t m;
  const int r = vest_decode_message(frame, len, &m, version);
  if (r != VEST_FRAME_OK)
    return r;
  if (m.type != VEST_TYPE_COMMAND && m.type != VEST_TYPE_STATUS)
    return VEST_FRAME_OTHER_TYPE;
  *p = m.packet;
  return VEST_FRAME_OK;
}

/* Checks one whole wire packet as vest_encode writes it (VEST_PACKET_SIZE bytes, both
 * delimiters, version 4); returns 1 and fills p when it is valid. */
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
  uint8_t peer_version;       /* VERSION of the last CRC-valid frame of a version we do not speak */
  uint16_t packets;           /* valid packets (wraps) */
  uint16_t rejected;          /* non-empty frames that failed a check (wraps) */
  uint16_t skipped;           /* bytes in rejected frames (wraps) */
  uint16_t version_mismatch;  /* CRC-valid frames of another protocol version (wraps) */
} vest_parser_t;

static inline void vest_parser_init(vest_parser_t* ps)
{
  memset(ps, 0, sizeof(*ps));
}

/* Feeds one byte. Returns 1 when it completed a valid packet of any type (copied to *out), else 0. */
static inline int vest_parser_feed_message(vest_parser_t* ps, uint8_t byte, vest_message_t* out)
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
  r = vest_decode_message(ps->buf, n, out, &version);
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

/* Feeds one byte. Returns 1 when it completed a valid COMMAND or STATUS (copied to *out), else 0
 * (a valid RANGE / BUTTONS / IMU is counted in packets and dropped). */
static inline int vest_parser_feed(vest_parser_t* ps, uint8_t byte, vest_packet_t* out)
{
  vest_message_t m;
  if (!vest_parser_feed_message(ps, byte, &m))
    return 0;
  if (m.type != VEST_TYPE_COMMAND && m.type != VEST_TYPE_STATUS)
    return 0;
  *out = m.packet;
  return 1;
}

/* ---- The ranger (HC-SR04 class): trigger, time the echo, median of the last 3 pings. ---- */

/* Echo pulse width -> mm at 343 m/s (round trip: width * 0.1715 mm/us), saturating. */
static inline uint16_t vest_echo_us_to_mm(uint32_t width_us)
{
  const uint32_t mm = (width_us * 343ul + 1000ul) / 2000ul;
  return mm > 0xFFFFul ? (uint16_t)0xFFFFu : (uint16_t)mm;
}

/* One ping from its echo line: `rose` = the line went high after the trigger, `fell` = and low
 * again, after width_us. Returns VEST_PING_*; *mm gets the distance of an echo. */
static inline uint8_t vest_classify_ping(uint8_t rose, uint8_t fell, uint32_t width_us, uint16_t* mm)
{
  *mm = 0u;
  if (!rose)
    return (uint8_t)VEST_PING_MISSING;
  if (!fell || width_us >= VEST_ECHO_TIMEOUT_US)
    return (uint8_t)VEST_PING_NO_ECHO;
  *mm = vest_echo_us_to_mm(width_us);
  if (*mm > VEST_RANGE_MAX_MM)
  {
    *mm = 0u;
    return (uint8_t)VEST_PING_NO_ECHO;  /* the sensor's own "nothing" pulse (about 38 ms) */
  }
  return (uint8_t)VEST_PING_ECHO;
}

typedef struct
{
  uint8_t result[3];  /* VEST_PING_* of the last 3 pings (ring) */
  uint16_t mm[3];
  uint8_t next, count;
  uint8_t seq;
} vest_ranger_t;

/* Adds one ping; once 3 pings are in, fills *out with the median of the last 3 (a ping without an
 * echo counts as farther than any echo) and returns 1, else 0. */
static inline int vest_ranger_ping(vest_ranger_t* rg, uint8_t result, uint16_t mm, vest_range_t* out)
{
  uint8_t i, echoes = 0u, missing = 0u;
  uint16_t a, b, c, t;
  rg->result[rg->next] = result;
  rg->mm[rg->next] = result == VEST_PING_ECHO ? mm : (uint16_t)0xFFFFu;
  rg->next = (uint8_t)((rg->next + 1u) % 3u);
  if (rg->count < 3u)
    rg->count++;
  if (rg->count < 3u)
    return 0;
  for (i = 0; i < 3u; ++i)
  {
    if (rg->result[i] == VEST_PING_ECHO)
      echoes++;
    else if (rg->result[i] == VEST_PING_MISSING)
      missing++;
  }
  out->seq = rg->seq++;
  out->echoes = echoes;
  out->range_mm = 0u;
  if (missing >= 2u)
    out->status = (uint8_t)VEST_RANGE_SENSOR_MISSING;
  else if (echoes < 2u)
    out->status = (uint8_t)VEST_RANGE_NO_ECHO;
  else
  {
    a = rg->mm[0];
    b = rg->mm[1];
    c = rg->mm[2];
    if (a > b) { t = a; a = b; b = t; }
    if (b > c) { t = b; b = c; c = t; }
    if (a > b) { t = a; a = b; b = t; }
    out->status = (uint8_t)VEST_RANGE_OK;
    out->range_mm = b;  /* the median; with 2 echoes the farther one (the third is "none") */
  }
  return 1;
}

/* ---- Push buttons: debounce, short / long presses. ---- */
typedef struct
{
  uint8_t raw;       /* last raw reading (1 = down) */
  uint8_t stable;    /* debounced state */
  uint8_t long_sent; /* this press already reported LONG */
  uint32_t raw_since_ms, down_since_ms;
} vest_button_t;

/* One reading of a button (1 = down) at now_ms: VEST_PRESS_LONG once it has been down
 * VEST_LONG_PRESS_MS, VEST_PRESS_SHORT when it is released before, else VEST_PRESS_NONE. */
static inline int vest_button_update(vest_button_t* b, uint8_t down, uint32_t now_ms)
{
  down = down ? 1u : 0u;
  if (down != b->raw)
  {
    b->raw = down;
    b->raw_since_ms = now_ms;
  }
  if (b->raw != b->stable && (uint32_t)(now_ms - b->raw_since_ms) >= VEST_DEBOUNCE_MS)
  {
    b->stable = b->raw;
    if (b->stable)
    {
      b->down_since_ms = now_ms;
      b->long_sent = 0u;
    }
    else if (!b->long_sent)
      return VEST_PRESS_SHORT;
  }
  if (b->stable && !b->long_sent && (uint32_t)(now_ms - b->down_since_ms) >= VEST_LONG_PRESS_MS)
  {
    b->long_sent = 1u;
    return VEST_PRESS_LONG;
  }
  return VEST_PRESS_NONE;
}

/* ---- The IMU: samples averaged over each VEST_IMU_PERIOD_MS window. ---- */
typedef struct
{
  int32_t gyro_sum[3], accel_sum[3];
  uint8_t samples;          /* read in this window (saturates at 255) */
  uint8_t seq;              /* of the next IMU packet */
  uint32_t window_start_ms;
} vest_imu_acc_t;

/* Saturates to int16. */
static inline int16_t vest_sat16(int32_t v)
{
  return v > 32767l ? (int16_t)32767 : v < -32767l ? (int16_t)-32767 : (int16_t)v;
}

/* Mean of n samples' sum, rounded half away from zero, saturated. */
static inline int16_t vest_mean16(int32_t sum, uint8_t n)
{
  const int32_t half = (int32_t)(n / 2u);
  return vest_sat16(sum >= 0 ? (sum + half) / (int32_t)n : (sum - half) / (int32_t)n);
}

/* Adds one reading (`ok` = 0: the sensor could not be read; gyro in mrad/s, accel in mm/s^2) at
 * now_ms. Returns 1 when the window is over (VEST_IMU_PERIOD_MS since it began) and *out holds
 * its IMU packet (the mean of its samples; SENSOR_MISSING when none could be read); a new window
 * begins. The reading that ends a window belongs to it. */
static inline int vest_imu_add(vest_imu_acc_t* acc, uint8_t ok, const int16_t* gyro, const int16_t* accel,
                               uint32_t now_ms, vest_imu_t* out)
{
  uint8_t i;
  if (ok && acc->samples < 255u)
  {
    for (i = 0; i < 3u; ++i)
    {
      acc->gyro_sum[i] += gyro[i];
      acc->accel_sum[i] += accel[i];
    }
    acc->samples++;
  }
  if ((uint32_t)(now_ms - acc->window_start_ms) < VEST_IMU_PERIOD_MS)
    return 0;
  memset(out, 0, sizeof(*out));
  out->seq = acc->seq++;
  out->t_ms = (uint16_t)(now_ms & 0xFFFFul);
  out->samples = acc->samples;
  out->status = acc->samples > 0u ? (uint8_t)VEST_IMU_OK : (uint8_t)VEST_IMU_SENSOR_MISSING;
  for (i = 0; acc->samples > 0u && i < 3u; ++i)
  {
    out->gyro[i] = vest_mean16(acc->gyro_sum[i], acc->samples);
    out->accel[i] = vest_mean16(acc->accel_sum[i], acc->samples);
  }
  for (i = 0; i < 3u; ++i)
    acc->gyro_sum[i] = acc->accel_sum[i] = 0;
  acc->samples = 0u;
  acc->window_start_ms = now_ms;
  return 1;
}

/* ---- The vest's behaviour (the firmware's loop, also run by the simulated vest). ---- */
typedef struct
{
  vest_parser_t parser;
  uint8_t duty[VEST_NUM_MOTORS]; /* what the PWM outputs drive now */
  uint8_t motors;                /* bit mask of motors with duty > 0 */
  uint8_t cmd_duty[VEST_NUM_MOTORS]; /* the last COMMAND's duties: driven while its pattern is on */
  vest_pattern_t pattern;        /* the pattern playing (the last COMMAND's) */
  uint32_t pattern_start_ms;     /* when it started (phase 0) */
  uint8_t have_pattern;          /* 1 once a COMMAND started a pattern (power-up: none) */
  uint8_t pattern_over;          /* its last pulse has ended: off until another pattern */
  uint16_t pattern_starts;       /* patterns started (restarts at phase 0; wraps) */
  uint8_t last_seq;              /* SEQ of the last accepted COMMAND */
  uint8_t have_command;          /* 1 once a COMMAND was accepted since the last timeout */
  uint32_t last_command_ms;
  uint16_t hold_ms;              /* the last COMMAND drives until last_command_ms + hold_ms */
  uint16_t timeouts;             /* watchdog trips (wraps) */
  uint16_t expiries;             /* commands that ran out of TTL (wraps) */
  uint8_t peer_version;          /* VERSION of the last accepted COMMAND (0 = none yet) */
  uint8_t reply_version;         /* VERSION to encode the STATUS vest_firmware_feed asked for */
  vest_ranger_t ranger;
  vest_button_t button[VEST_NUM_BUTTONS];
  vest_buttons_t buttons;        /* counters and held state, sent in BUTTONS */
  uint32_t last_buttons_ms;      /* when the last BUTTONS went out */
  vest_imu_acc_t imu;            /* the IMU samples of the current window */
} vest_firmware_t;

static inline void vest_firmware_init(vest_firmware_t* fw, uint32_t now_ms)
{
  memset(fw, 0, sizeof(*fw));
  vest_parser_init(&fw->parser);
  fw->last_command_ms = now_ms;
  fw->last_buttons_ms = now_ms;
  fw->imu.window_start_ms = now_ms;
  fw->reply_version = (uint8_t)VEST_PROTOCOL_VERSION;
}

/* 1 when the PC speaks version 3 or later (RANGE and BUTTONS are sent to it), else 0. */
static inline int vest_firmware_peer_v3(const vest_firmware_t* fw)
{
  return fw->peer_version >= 3u;
}

/* VERSION of the RANGE / BUTTONS / IMU packets: the PC's (3, 4 or ours; the layout is the same). */
static inline uint8_t vest_firmware_sensor_version(const vest_firmware_t* fw)
{
  return fw->peer_version >= VEST_PROTOCOL_VERSION ? (uint8_t)VEST_PROTOCOL_VERSION : fw->peer_version;
}

static inline void vest_firmware_all_off(vest_firmware_t* fw)
{
  uint8_t i;
  for (i = 0; i < VEST_NUM_MOTORS; ++i)
    fw->duty[i] = 0u;
  fw->motors = 0u;
}

/* Sets the outputs from the last COMMAND and its pattern at now_ms (all off without a valid
 * COMMAND). Returns 1 when an output changed. */
static inline int vest_firmware_render(vest_firmware_t* fw, uint32_t now_ms)
{
  uint8_t i, d, motors = 0u, changed = 0u;
  uint32_t t, len;
  int on = 0;
  if (fw->have_command && !fw->pattern_over)
  {
    t = (uint32_t)(now_ms - fw->pattern_start_ms);
    len = vest_pattern_length_ms(&fw->pattern);
    /* A counted pattern, once over, stays over (t would wrap after 49.7 days and replay it). */
    if (len != VEST_NEVER && t >= len)
      fw->pattern_over = 1u;
    else
      on = vest_pattern_on(&fw->pattern, t);
  }
  for (i = 0; i < VEST_NUM_MOTORS; ++i)
  {
    d = on ? fw->cmd_duty[i] : (uint8_t)0u;
    if (d != fw->duty[i])
      changed = 1u;
    fw->duty[i] = d;
    if (d > 0u)
      motors = (uint8_t)(motors | (1u << i));
  }
  fw->motors = motors;
  return changed;
}

/* Fills a STATUS with what the outputs do now and the pattern playing. */
static inline void vest_firmware_status(const vest_firmware_t* fw, vest_packet_t* status)
{
  uint8_t i;
  status->type = VEST_TYPE_STATUS;
  status->seq = fw->last_seq;
  status->motors = fw->motors;
  for (i = 0; i < VEST_NUM_MOTORS; ++i)
    status->intensity[i] = fw->duty[i];
  status->ttl_ms = 0u;
  status->pattern = fw->pattern;
}

/* Feeds one received byte. Returns VEST_FEED_APPLIED when a valid COMMAND (version 2 .. 5)
 * was applied, and VEST_FEED_VERSION_REPLY when a CRC-valid frame of a version we do not speak
 * ended (counted in parser.version_mismatch; nothing applied); in both cases *status holds the
 * STATUS packet to send back, in version fw->reply_version (the COMMAND's; ours in a version
 * reply, so that peer learns it). STATUS packets and anything invalid are ignored
 * (VEST_FEED_NONE).
 * A COMMAND carrying the pattern that plays continues it (phase from its start); another
 * pattern starts at phase 0 now. A version-2 / 3 COMMAND has no pattern bytes: steady. */
static inline int vest_firmware_feed(vest_firmware_t* fw, uint8_t byte, uint32_t now_ms,
                                     vest_packet_t* status)
{
  vest_message_t m;
  vest_packet_t p;
  uint8_t i;
  const uint16_t mismatches = fw->parser.version_mismatch;
  if (!vest_parser_feed_message(&fw->parser, byte, &m))
  {
    if (fw->parser.version_mismatch == mismatches)
      return VEST_FEED_NONE;
    vest_firmware_status(fw, status); /* our version in the reply: the peer can report it */
    fw->reply_version = (uint8_t)VEST_PROTOCOL_VERSION;
    return VEST_FEED_VERSION_REPLY;
  }
  if (m.type != VEST_TYPE_COMMAND)
    return VEST_FEED_NONE;
  p = m.packet;
  fw->peer_version = m.version;
  fw->reply_version = m.version;
  if (!fw->have_pattern || !vest_pattern_equal(&p.pattern, &fw->pattern))
  {
    fw->pattern = p.pattern;
    fw->pattern_start_ms = now_ms;
    fw->have_pattern = 1u;
    fw->pattern_over = 0u;
    fw->pattern_starts++;
  }
  for (i = 0; i < VEST_NUM_MOTORS; ++i)
    fw->cmd_duty[i] = vest_motor_duty(&p, i);
  fw->last_seq = p.seq;
  fw->have_command = 1u;
  fw->last_command_ms = now_ms;
  fw->hold_ms = p.ttl_ms < VEST_WATCHDOG_MS ? p.ttl_ms : (uint16_t)VEST_WATCHDOG_MS;
  vest_firmware_render(fw, now_ms);
  vest_firmware_status(fw, status);
  return VEST_FEED_APPLIED;
}

/* One ping of the ranger (vest_classify_ping's result). Returns 1 when *out holds a RANGE to
 * send (3 pings in and the PC speaks version 3 or later; encode it in
 * vest_firmware_sensor_version), else 0. */
static inline int vest_firmware_range(vest_firmware_t* fw, uint8_t ping, uint16_t mm, vest_range_t* out)
{
  return vest_ranger_ping(&fw->ranger, ping, mm, out) && vest_firmware_peer_v3(fw);
}

/* Reads the two buttons (1 = down) at now_ms. Returns 1 when *out holds a BUTTONS to send (a
 * press, a change of HELD, or the heartbeat is due, and the PC speaks version 3 or later;
 * encode it in vest_firmware_sensor_version), else 0. */
static inline int vest_firmware_buttons(vest_firmware_t* fw, uint8_t a_down, uint8_t b_down, uint32_t now_ms,
                                        vest_buttons_t* out)
{
  uint8_t i, held = 0u, event = 0u;
  int r;
  for (i = 0; i < VEST_NUM_BUTTONS; ++i)
  {
    r = vest_button_update(&fw->button[i], i == 0u ? a_down : b_down, now_ms);
    if (r == VEST_PRESS_SHORT)
    {
      if (i == 0u) fw->buttons.short_a++; else fw->buttons.short_b++;
      event = 1u;
    }
    else if (r == VEST_PRESS_LONG)
    {
      if (i == 0u) fw->buttons.long_a++; else fw->buttons.long_b++;
      event = 1u;
    }
    if (fw->button[i].stable)
      held = (uint8_t)(held | (1u << i));
  }
  if (held != fw->buttons.held)
    event = 1u;
  fw->buttons.held = held;
  if (!event && (uint32_t)(now_ms - fw->last_buttons_ms) < VEST_BUTTONS_PERIOD_MS)
    return 0;
  if (!vest_firmware_peer_v3(fw))
    return 0;
  fw->last_buttons_ms = now_ms;
  *out = fw->buttons;
  fw->buttons.seq++;
  return 1;
}

/* One IMU reading (see vest_imu_add) at now_ms. Returns 1 when *out holds an IMU packet to send
 * (a window is over and the PC speaks version 5; encode it in vest_firmware_sensor_version),
 * else 0. The windows run whoever listens, so the first one sent is a whole one. */
static inline int vest_firmware_imu(vest_firmware_t* fw, uint8_t ok, const int16_t* gyro, const int16_t* accel,
                                    uint32_t now_ms, vest_imu_t* out)
{
  return vest_imu_add(&fw->imu, ok, gyro, accel, now_ms, out) && fw->peer_version >= VEST_IMU_VERSION;
}

/* TTL, watchdog and the pattern's pulses; call every loop (the pulse edges are then as exact as
 * millis(): a millisecond on the ATmega, whatever the serial link does). Returns VEST_TICK_EXPIRED / VEST_TICK_WATCHDOG when it
 * just switched the motors off (the command's TTL ran out / no COMMAND for VEST_WATCHDOG_MS),
 * VEST_TICK_PULSE when the pattern switched an output, else VEST_TICK_NONE. Unsigned
 * subtraction keeps it right across the millis() wrap (49.7 days). */
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
  if (fw->have_command && vest_firmware_render(fw, now_ms))
    return VEST_TICK_PULSE;
  return VEST_TICK_NONE;
}

/* ms from now_ms until vest_firmware_tick may change the outputs by itself (a pulse edge, the
 * TTL or the watchdog; possibly earlier, never later); VEST_NEVER when nothing is due. The
 * simulated vest sleeps this long at most; the sketch just ticks every loop. */
static inline uint32_t vest_firmware_next_change_ms(const vest_firmware_t* fw, uint32_t now_ms)
{
  uint32_t since, due, edge;
  if (!fw->have_command)
    return VEST_NEVER;
  since = (uint32_t)(now_ms - fw->last_command_ms);
  due = since > fw->hold_ms ? 0u : (uint32_t)fw->hold_ms + 1u - since;  /* off at hold_ms + 1 */
  if (!fw->pattern_over)
  {
    edge = vest_pattern_next_edge_ms(&fw->pattern, (uint32_t)(now_ms - fw->pattern_start_ms));
    if (edge < due)
      due = edge;
  }
  return due;
}

#ifdef __cplusplus
} /* extern "C" */
#endif

#endif /* ASSISTIVE_TACTILE_VEST_PROTOCOL_H */
