/* Compiled as C99: vest_protocol.h must stay C-compatible for the Arduino side. Round trips of
 * every packet type (COMMAND with its pulse pattern, RANGE, BUTTONS, IMU), run by test_vest_protocol
 * (CRoundTrip). */
#include "assistive_tactile/vest_protocol.h"

int assistive_tactile_protocol_c_check(void);
int assistive_tactile_protocol_c_check(void)
{
  /* version 4: the pattern comes back field for field */
  vest_packet_t p = { VEST_TYPE_COMMAND, 1, 0x5, { 10, 0, 30, 0 }, 200, { 9, 15, 15, 2 } };
  uint8_t buf[VEST_PACKET_SIZE];
  vest_packet_t q;
  vest_encode(&p, buf);
  if (!vest_decode(buf, &q))
    return 0;
  return q.seq == 1 && q.motors == 0x5 && q.intensity[2] == 30 && q.ttl_ms == 200 && vest_pattern_equal(&p.pattern, &q.pattern);
}

/* RANGE and BUTTONS through the streaming parser; returns 1 when both come back field for field. */
int assistive_tactile_protocol_c_check_v3(void);
int assistive_tactile_protocol_c_check_v3(void)
{
  vest_range_t r = { 7, VEST_RANGE_OK, 1234, 3 };
  vest_buttons_t b = { 9, 0x2, 1, 2, 3, 4 };
  uint8_t buf[VEST_BUTTONS_PACKET_SIZE];
  vest_parser_t ps;
  vest_message_t m;
  uint8_t i;
  int got_r = 0, got_b = 0;
  vest_parser_init(&ps);
  vest_encode_range(&r, buf);
  for (i = 0; i < VEST_RANGE_PACKET_SIZE; ++i)
    if (vest_parser_feed_message(&ps, buf[i], &m))
      got_r = m.version == VEST_PROTOCOL_VERSION && m.type == VEST_TYPE_RANGE && m.range.seq == 7 &&
              m.range.status == VEST_RANGE_OK && m.range.range_mm == 1234 && m.range.echoes == 3;
  vest_encode_buttons(&b, buf);
  for (i = 0; i < VEST_BUTTONS_PACKET_SIZE; ++i)
    if (vest_parser_feed_message(&ps, buf[i], &m))
      got_b = m.type == VEST_TYPE_BUTTONS && m.buttons.seq == 9 && m.buttons.held == 2 && m.buttons.short_a == 1 &&
              m.buttons.long_a == 2 && m.buttons.short_b == 3 && m.buttons.long_b == 4;
  return got_r && got_b;
}

/* IMU (version 5) through the streaming parser; returns 1 when it comes back field for field. */
int assistive_tactile_protocol_c_check_v5(void);
int assistive_tactile_protocol_c_check_v5(void)
{
  vest_imu_t u = { 3, VEST_IMU_OK, 4, 65535u, { -1, 2, -32767 }, { 32767, -9, 9807 } };
  uint8_t buf[VEST_MAX_PACKET_SIZE];
  vest_parser_t ps;
  vest_message_t m;
  uint8_t i;
  int got = 0;
  vest_parser_init(&ps);
  vest_encode_imu(&u, buf);
  for (i = 0; i < VEST_IMU_PACKET_SIZE; ++i)
    if (vest_parser_feed_message(&ps, buf[i], &m))
      got = m.version == VEST_IMU_VERSION && m.type == VEST_TYPE_IMU && m.imu.seq == 3 && m.imu.samples == 4 &&
            m.imu.t_ms == 65535u && m.imu.gyro[0] == -1 && m.imu.gyro[2] == -32767 && m.imu.accel[0] == 32767 &&
            m.imu.accel[2] == 9807;
  return got;
}
