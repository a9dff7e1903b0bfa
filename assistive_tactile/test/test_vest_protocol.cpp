// The packet codec, the COBS framing, the streaming parser and the firmware behaviour of
// vest_protocol.h (the code the Arduino sketch runs, compiled here on the host).
#include <gtest/gtest.h>

#include <functional>
#include <random>
#include <vector>

#include "assistive_tactile/vest_protocol.h"

namespace
{
vest_packet_t command(uint8_t seq, uint8_t motors, uint8_t i0, uint8_t i1, uint8_t i2, uint8_t i3,
                      uint16_t ttl_ms = 1000, vest_pattern_t pattern = vest_pattern_t{ 0, 0, 0, 0 })
{
  vest_packet_t p{};
  p.pattern = pattern;
  p.ttl_ms = ttl_ms;
  p.type = VEST_TYPE_COMMAND;
  p.seq = seq;
  p.motors = motors;
  p.intensity[0] = i0;
  p.intensity[1] = i1;
  p.intensity[2] = i2;
  p.intensity[3] = i3;
  return p;
}

std::vector<uint8_t> bytes(const vest_packet_t& p)
{
  std::vector<uint8_t> b(VEST_PACKET_SIZE);
  vest_encode(&p, b.data());
  return b;
}

/// A COMMAND / STATUS as a version-4 peer writes it (the same bytes as ours but VERSION).
std::vector<uint8_t> bytesV4(const vest_packet_t& p)
{
  std::vector<uint8_t> b(VEST_PACKET_SIZE);
  b.resize(vest_encode_version(&p, 4, b.data()));
  return b;
}

/// The frame of a packet with hand-made raw bytes (VERSION .. before the CRC): CRC appended,
/// COBS-encoded, between delimiters.
std::vector<uint8_t> frameOf(const std::vector<uint8_t>& raw)
{
  std::vector<uint8_t> out(raw.size() + 7);
  out.resize(vest_frame(raw.data(), static_cast<uint8_t>(raw.size()), out.data()));
  return out;
}

bool same(const vest_packet_t& a, const vest_packet_t& b)
{
  return a.type == b.type && a.seq == b.seq && a.motors == b.motors && a.ttl_ms == b.ttl_ms &&
         std::equal(a.intensity, a.intensity + 4, b.intensity) && vest_pattern_equal(&a.pattern, &b.pattern);
}

std::vector<vest_packet_t> feedAll(vest_parser_t* ps, const std::vector<uint8_t>& stream)
{
  std::vector<vest_packet_t> out;
  for (uint8_t b : stream)
  {
    vest_packet_t p;
    if (vest_parser_feed(ps, b, &p))
      out.push_back(p);
  }
  return out;
}

void append(std::vector<uint8_t>* s, const std::vector<uint8_t>& b)
{
  s->insert(s->end(), b.begin(), b.end());
}
}  // namespace

TEST(VestProtocol, Crc32cCheckValue)
{
  // CRC-32C (iSCSI / Castagnoli) catalogue check value.
  const uint8_t msg[] = { '1', '2', '3', '4', '5', '6', '7', '8', '9' };
  EXPECT_EQ(vest_crc32c(msg, 9), 0xE3069283u);
  EXPECT_EQ(vest_crc32c(msg, 0), 0x00000000u);
}

TEST(VestProtocol, CobsTable)
{
  // Wikipedia's COBS examples (frames under 254 bytes).
  const std::vector<std::pair<std::vector<uint8_t>, std::vector<uint8_t>>> table = {
    { { 0x00 }, { 0x01, 0x01 } },
    { { 0x00, 0x00 }, { 0x01, 0x01, 0x01 } },
    { { 0x00, 0x11, 0x00 }, { 0x01, 0x02, 0x11, 0x01 } },
    { { 0x11, 0x22, 0x00, 0x33 }, { 0x03, 0x11, 0x22, 0x02, 0x33 } },
    { { 0x11, 0x22, 0x33, 0x44 }, { 0x05, 0x11, 0x22, 0x33, 0x44 } },
    { { 0x11, 0x00, 0x00, 0x00 }, { 0x02, 0x11, 0x01, 0x01, 0x01 } },
  };
  for (const auto& r : table)
  {
    std::vector<uint8_t> enc(r.first.size() + 1);
    ASSERT_EQ(vest_cobs_encode(r.first.data(), static_cast<uint8_t>(r.first.size()), enc.data()), r.second.size());
    EXPECT_EQ(enc, r.second);
    std::vector<uint8_t> dec(r.second.size());
    ASSERT_EQ(vest_cobs_decode(r.second.data(), static_cast<uint8_t>(r.second.size()), dec.data()),
              static_cast<int>(r.first.size()));
    dec.resize(r.first.size());
    EXPECT_EQ(dec, r.first);
  }
  const uint8_t broken[] = { 0x05, 0x11, 0x22 };  // code says 4 data bytes, only 2 follow
  uint8_t out[8];
  EXPECT_EQ(vest_cobs_decode(broken, 3, out), -1);
}

TEST(VestProtocol, KnownEncodingVersion4)
{
  // COMMAND seq 7, motors 0x5, duties 200 0 100 0, TTL 300 ms, pattern #9 150 ms on 150 ms off
  // x2 (a veer burst). Raw: 04 01 07 05 C8 00 64 00 2C 01 09 0F 0F 02, CRC-32C 0x7D506305 (computed
  // independently, low byte first); COBS groups end at the two zeros (codes 06, 02, 0B).
  const std::vector<uint8_t> want = { 0x00, 0x06, 0x04, 0x01, 0x07, 0x05, 0xC8, 0x02, 0x64, 0x0B, 0x2C,
                                      0x01, 0x09, 0x0F, 0x0F, 0x02, 0x05, 0x63, 0x50, 0x7D, 0x00 };
  const uint8_t raw[] = { 4, 1, 7, 5, 200, 0, 100, 0, 0x2C, 1, 9, 15, 15, 2 };
  EXPECT_EQ(vest_crc32c(raw, sizeof(raw)), 0x7D506305u);
  const vest_packet_t p = command(7, 0x5, 200, 0, 100, 0, 300, vest_pattern_t{ 9, 15, 15, 2 });
  EXPECT_EQ(bytesV4(p), want);
  ASSERT_EQ(want.size(), VEST_PACKET_SIZE);
  EXPECT_EQ(VEST_PACKET_SIZE, 21u);
  EXPECT_EQ(VEST_RAW_SIZE, 18u);
  std::vector<uint8_t> got(VEST_PACKET_SIZE);
  EXPECT_EQ(vest_encode_version(&p, 4, got.data()), 21u);
  EXPECT_EQ(got, want);
  // ... and back, field for field.
  vest_packet_t q{};
  ASSERT_TRUE(vest_decode(want.data(), &q));
  EXPECT_EQ(q.type, VEST_TYPE_COMMAND);
  EXPECT_EQ(q.seq, 7);
  EXPECT_EQ(q.motors, 0x5);
  EXPECT_EQ(q.intensity[0], 200);
  EXPECT_EQ(q.intensity[1], 0);
  EXPECT_EQ(q.intensity[2], 100);
  EXPECT_EQ(q.intensity[3], 0);
  EXPECT_EQ(q.ttl_ms, 300);
  EXPECT_EQ(q.pattern.id, 9);
  EXPECT_EQ(q.pattern.on_10ms, 15);
  EXPECT_EQ(q.pattern.off_10ms, 15);
  EXPECT_EQ(q.pattern.count, 2);

  // STATUS: what the outputs do now (left shoulder 179) and the pattern playing; five zeros in a
  // row (I1..I3, TTL) are five COBS codes 01. CRC 0x93C3CB94.
  vest_packet_t st = command(7, 0x1, 179, 0, 0, 0, 0, vest_pattern_t{ 9, 15, 15, 2 });
  st.type = VEST_TYPE_STATUS;
  const std::vector<uint8_t> want_st = { 0x00, 0x06, 0x04, 0x02, 0x07, 0x01, 0xB3, 0x01, 0x01, 0x01, 0x01,
                                         0x09, 0x09, 0x0F, 0x0F, 0x02, 0x94, 0xCB, 0xC3, 0x93, 0x00 };
  EXPECT_EQ(bytesV4(st), want_st);
  ASSERT_TRUE(vest_decode(want_st.data(), &q));
  EXPECT_TRUE(same(q, st));
  // Version 5 writes the same bytes with VERSION 5 (and so another CRC).
  const std::vector<uint8_t> v5 = bytes(p);
  ASSERT_EQ(v5.size(), want.size());
  EXPECT_EQ(v5[2], 5);
  EXPECT_TRUE(std::equal(v5.begin() + 3, v5.begin() + 16, want.begin() + 3));
  uint8_t version = 0;
  ASSERT_EQ(vest_decode_frame(v5.data() + 1, static_cast<uint8_t>(v5.size() - 2), &q, &version), VEST_FRAME_OK);
  EXPECT_EQ(version, 5);
  EXPECT_TRUE(same(q, p));
}

TEST(VestProtocol, KnownEncodingImu)
{
  // IMU seq 7, OK, 4 samples, T_MS 0x1234, gyro (10, -2, 1571) mrad/s, accel (120, -35, 9807)
  // mm/s^2. Raw 05 05 07 00 04 34 12 0A 00 FE FF 23 06 78 00 DD FF 4F 26, CRC-32C 0x0F711F56
  // (computed independently, low byte first).
  const std::vector<uint8_t> want = { 0x00, 0x04, 0x05, 0x05, 0x07, 0x05, 0x04, 0x34, 0x12, 0x0A, 0x06, 0xFE, 0xFF,
                                      0x23, 0x06, 0x78, 0x09, 0xDD, 0xFF, 0x4F, 0x26, 0x56, 0x1F, 0x71, 0x0F, 0x00 };
  ASSERT_EQ(want.size(), VEST_IMU_PACKET_SIZE);
  vest_imu_t u{};
  u.seq = 7;
  u.status = VEST_IMU_OK;
  u.samples = 4;
  u.t_ms = 0x1234;
  u.gyro[0] = 10; u.gyro[1] = -2; u.gyro[2] = 1571;
  u.accel[0] = 120; u.accel[1] = -35; u.accel[2] = 9807;
  std::vector<uint8_t> got(VEST_IMU_PACKET_SIZE);
  vest_encode_imu(&u, got.data());
  EXPECT_EQ(got, want);
  // ... back through the streaming parser, field for field.
  vest_parser_t ps;
  vest_parser_init(&ps);
  vest_message_t m{};
  int n = 0;
  for (uint8_t b : want)
    n += vest_parser_feed_message(&ps, b, &m);
  ASSERT_EQ(n, 1);
  EXPECT_EQ(m.version, 5);
  EXPECT_EQ(m.type, VEST_TYPE_IMU);
  EXPECT_EQ(m.imu.seq, 7);
  EXPECT_EQ(m.imu.status, VEST_IMU_OK);
  EXPECT_EQ(m.imu.samples, 4);
  EXPECT_EQ(m.imu.t_ms, 0x1234);
  for (int i = 0; i < 3; ++i)
  {
    EXPECT_EQ(m.imu.gyro[i], u.gyro[i]);
    EXPECT_EQ(m.imu.accel[i], u.accel[i]);
  }
  // A missing sensor: twelve zeros in a row are twelve COBS codes 01. CRC 0x858A0CF2.
  const std::vector<uint8_t> want_missing = { 0x00, 0x05, 0x05, 0x05, 0x08, 0x01, 0x02, 0x10, 0x01, 0x01, 0x01, 0x01, 0x01,
                                              0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x05, 0xF2, 0x0C, 0x8A, 0x85, 0x00 };
  vest_imu_t missing{};
  missing.seq = 8;
  missing.status = VEST_IMU_SENSOR_MISSING;
  missing.t_ms = 0x10;
  vest_encode_imu(&missing, got.data());
  EXPECT_EQ(got, want_missing);
  // Not a COMMAND / STATUS.
  vest_packet_t q;
  EXPECT_EQ(vest_decode_frame(want.data() + 1, static_cast<uint8_t>(want.size() - 2), &q, nullptr), VEST_FRAME_OTHER_TYPE);
}

TEST(VestProtocol, ImuBadFieldsRejected)
{
  vest_message_t m;
  auto decode = [&](const std::vector<uint8_t>& raw) {
    const std::vector<uint8_t> f = frameOf(raw);
    return vest_decode_message(f.data() + 1, static_cast<uint8_t>(f.size() - 2), &m, nullptr);
  };
  const std::vector<uint8_t> ok = { 5, 5, 1, 0, 4, 0, 1, 10, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0x4F, 0x26 };
  EXPECT_EQ(decode(ok), VEST_FRAME_OK);
  std::vector<uint8_t> r = ok;
  r[3] = 2;  // unknown STATUS
  EXPECT_EQ(decode(r), VEST_FRAME_FIELD);
  r = ok;
  r[4] = 0;  // OK with no sample
  EXPECT_EQ(decode(r), VEST_FRAME_FIELD);
  r = ok;
  r[3] = VEST_IMU_SENSOR_MISSING;  // missing, yet measured something
  EXPECT_EQ(decode(r), VEST_FRAME_FIELD);
  r[4] = 0;
  EXPECT_EQ(decode(r), VEST_FRAME_FIELD);  // (the gyro and accel still say something)
  std::fill(r.begin() + 7, r.end(), 0);
  EXPECT_EQ(decode(r), VEST_FRAME_OK);
  r = ok;
  r.push_back(0);  // a byte long, a byte short
  EXPECT_EQ(decode(r), VEST_FRAME_LENGTH);
  r.resize(ok.size() - 1);
  EXPECT_EQ(decode(r), VEST_FRAME_LENGTH);
  r = ok;
  r[0] = 4;  // no IMU in version 4
  EXPECT_EQ(decode(r), VEST_FRAME_FIELD);
}

TEST(VestProtocol, KnownEncodingVersions2And3)
{
  // The same COMMAND as an old peer gets it: 14 bytes (no pattern bytes), 17 on the wire, the
  // bytes the version-2 / 3 protocol wrote. CRC-32C 0x539A7CF8 (v3), 0x98CC075D (v2).
  const std::vector<uint8_t> want3 = { 0x00, 0x06, 0x03, 0x01, 0x07, 0x05, 0xC8, 0x02, 0x64,
                                       0x07, 0x2C, 0x01, 0xF8, 0x7C, 0x9A, 0x53, 0x00 };
  const std::vector<uint8_t> want2 = { 0x00, 0x06, 0x02, 0x01, 0x07, 0x05, 0xC8, 0x02, 0x64,
                                       0x07, 0x2C, 0x01, 0x5D, 0x07, 0xCC, 0x98, 0x00 };
  // The pattern cannot be carried: dropped (an old bridge's COMMAND is steady).
  const vest_packet_t p = command(7, 0x5, 200, 0, 100, 0, 300, vest_pattern_t{ 9, 15, 15, 2 });
  for (const auto& vw : { std::make_pair(uint8_t(3), want3), std::make_pair(uint8_t(2), want2) })
  {
    std::vector<uint8_t> got(VEST_PACKET_SIZE, 0xEE);
    ASSERT_EQ(vest_encode_version(&p, vw.first, got.data()), VEST_PACKET_SIZE_V3);
    got.resize(VEST_PACKET_SIZE_V3);
    EXPECT_EQ(got, vw.second) << int(vw.first);
    EXPECT_EQ(vest_command_packet_size(vw.first), 17u);
    vest_packet_t q{};
    uint8_t version = 0;
    ASSERT_EQ(vest_decode_frame(got.data() + 1, static_cast<uint8_t>(got.size() - 2), &q, &version), VEST_FRAME_OK);
    EXPECT_EQ(version, vw.first);
    EXPECT_EQ(q.seq, 7);
    EXPECT_EQ(q.intensity[0], 200);
    EXPECT_EQ(q.ttl_ms, 300);
    EXPECT_EQ(q.pattern.id, 0);  // steady
    EXPECT_EQ(q.pattern.on_10ms, 0);
    EXPECT_EQ(q.pattern.off_10ms, 0);
    EXPECT_EQ(q.pattern.count, 0);
  }
}

TEST(VestProtocol, PatternFieldsAndLengthsByVersion)
{
  vest_packet_t q;
  auto decode = [&](const std::vector<uint8_t>& raw) {
    const std::vector<uint8_t> f = frameOf(raw);
    return vest_decode_frame(f.data() + 1, static_cast<uint8_t>(f.size() - 2), &q, nullptr);
  };
  // Version 4: 14 bytes before the CRC. Every pattern field value is legal with ON > 0.
  EXPECT_EQ(decode({ 4, 1, 1, 1, 9, 0, 0, 0, 100, 0, 255, 255, 255, 255 }), VEST_FRAME_OK);
  EXPECT_EQ(q.pattern.id, 255);
  EXPECT_EQ(q.pattern.on_10ms, 255);
  EXPECT_EQ(q.pattern.off_10ms, 255);
  EXPECT_EQ(q.pattern.count, 255);
  EXPECT_EQ(decode({ 4, 1, 1, 1, 9, 0, 0, 0, 100, 0, 0, 10, 0, 0 }), VEST_FRAME_OK);  // id 0, endless pulses
  EXPECT_EQ(decode({ 4, 1, 1, 1, 9, 0, 0, 0, 100, 0, 7, 0, 0, 0 }), VEST_FRAME_OK);   // steady #7
  // A steady pattern carries no timing: OFF / COUNT with ON 0 is an illegal field.
  EXPECT_EQ(decode({ 4, 1, 1, 1, 9, 0, 0, 0, 100, 0, 7, 0, 10, 0 }), VEST_FRAME_FIELD);
  EXPECT_EQ(decode({ 4, 1, 1, 1, 9, 0, 0, 0, 100, 0, 7, 0, 0, 2 }), VEST_FRAME_FIELD);
  EXPECT_EQ(decode({ 4, 2, 1, 1, 9, 0, 0, 0, 0, 0, 7, 0, 0, 2 }), VEST_FRAME_FIELD);  // STATUS too
  // ... and the encoder never writes one (a sender's stray fields are dropped).
  const vest_packet_t stray = command(1, 0x1, 9, 0, 0, 0, 100, vest_pattern_t{ 7, 0, 10, 2 });
  std::vector<uint8_t> b = bytes(stray);
  ASSERT_TRUE(vest_decode(b.data(), &q));
  EXPECT_EQ(q.pattern.id, 7);
  EXPECT_EQ(q.pattern.off_10ms, 0);
  EXPECT_EQ(q.pattern.count, 0);
  // The length belongs to the version: a version-4 COMMAND without its pattern bytes, a
  // version-3 one with them, one byte short or long: rejected.
  EXPECT_EQ(decode({ 4, 1, 1, 1, 9, 0, 0, 0, 100, 0 }), VEST_FRAME_LENGTH);
  EXPECT_EQ(decode({ 4, 1, 1, 1, 9, 0, 0, 0, 100, 0, 7, 10, 10 }), VEST_FRAME_LENGTH);
  EXPECT_EQ(decode({ 4, 1, 1, 1, 9, 0, 0, 0, 100, 0, 7, 10, 10, 1, 0 }), VEST_FRAME_LENGTH);
  EXPECT_EQ(decode({ 3, 1, 1, 1, 9, 0, 0, 0, 100, 0, 7, 10, 10, 1 }), VEST_FRAME_LENGTH);
  EXPECT_EQ(decode({ 2, 1, 1, 1, 9, 0, 0, 0, 100, 0, 7, 10, 10, 1 }), VEST_FRAME_LENGTH);
  EXPECT_EQ(decode({ 3, 1, 1, 1, 9, 0, 0, 0, 100, 0 }), VEST_FRAME_OK);
  EXPECT_EQ(decode({ 4, 1, 1, 0x21, 9, 0, 0, 0, 100, 0, 7, 10, 10, 1 }), VEST_FRAME_FIELD);  // reserved motor bit
}

TEST(VestProtocol, PatternTiming)
{
  // vest_pattern_on: the veer burst (150 / 150 ms x2) on at 0-149 and 300-449 ms only.
  const vest_pattern_t veer{ 5, 15, 15, 2 };
  for (uint32_t t = 0; t < 2000; ++t)
    ASSERT_EQ(vest_pattern_on(&veer, t), (t < 150 || (t >= 300 && t < 450)) ? 1 : 0) << t;
  EXPECT_EQ(vest_pattern_length_ms(&veer), 450u);
  struct Row
  {
    vest_pattern_t p;
    uint32_t length_ms;
    std::vector<std::pair<uint32_t, uint32_t>> next_edge;  // t -> ms to the next edge
  };
  const std::vector<Row> rows = {
    { veer, 450, { { 0, 150 }, { 149, 1 }, { 150, 150 }, { 299, 1 }, { 300, 150 }, { 449, 1 }, { 450, VEST_NEVER }, { 5000, VEST_NEVER } } },
    { { 1, 0, 0, 0 }, VEST_NEVER, { { 0, VEST_NEVER }, { 123456, VEST_NEVER } } },                  // steady
    { { 2, 10, 0, 1 }, 100, { { 0, 100 }, { 99, 1 }, { 100, VEST_NEVER } } },                       // walk-on tick
    { { 3, 10, 10, 3 }, 500, { { 0, 100 }, { 100, 100 }, { 450, 50 }, { 500, VEST_NEVER } } },      // unsure
    { { 4, 80, 0, 1 }, 800, { { 0, 800 }, { 800, VEST_NEVER } } },                                  // stop-and-turn
    { { 5, 10, 10, 0 }, VEST_NEVER, { { 0, 100 }, { 150, 50 }, { 1000000, 100 } } },                // endless
  };
  for (const Row& r : rows)
  {
    EXPECT_EQ(vest_pattern_length_ms(&r.p), r.length_ms) << int(r.p.id);
    for (const auto& e : r.next_edge)
      EXPECT_EQ(vest_pattern_next_edge_ms(&r.p, e.first), e.second) << int(r.p.id) << " at " << e.first;
  }
  // Equality is all four fields.
  vest_pattern_t other = veer;
  EXPECT_TRUE(vest_pattern_equal(&veer, &other));
  other.count = 3;
  EXPECT_FALSE(vest_pattern_equal(&veer, &other));
}

TEST(VestProtocol, NoDelimiterInsideAnyPacket)
{
  std::mt19937 rng(5);
  for (int i = 0; i < 20000; ++i)
  {
    const uint32_t r = rng();
    const std::vector<uint8_t> b = bytes(command(static_cast<uint8_t>(r), static_cast<uint8_t>(r >> 8) & 0xF,
                                               static_cast<uint8_t>(r >> 12), static_cast<uint8_t>(r >> 20),
                                               static_cast<uint8_t>(i % 3 ? 0 : r >> 24), 0));
    ASSERT_EQ(b.front(), 0);
    ASSERT_EQ(b.back(), 0);
    for (size_t k = 1; k + 1 < b.size(); ++k)
      ASSERT_NE(b[k], 0) << i;
  }
}

TEST(VestProtocol, RoundTripTable)
{
  const std::vector<vest_packet_t> table = {
    command(0, 0x0, 0, 0, 0, 0),       command(1, 0x1, 255, 0, 0, 0),   command(2, 0x2, 0, 128, 0, 0),
    command(3, 0x4, 0, 0, 1, 0),       command(4, 0x8, 0, 0, 0, 77),    command(255, 0xF, 255, 255, 255, 255),
    command(9, 0x3, 0xA5, 0xA5, 0, 0),  // old SYNC values inside the payload
    command(10, 0x1, 179, 0, 0, 0, 200, vest_pattern_t{ 17, 15, 15, 2 }),  // veer burst
    command(11, 0xC, 0, 0, 255, 255, 65535, vest_pattern_t{ 255, 10, 10, 3 }),  // unsure
    command(12, 0x3, 140, 140, 0, 0, 0, vest_pattern_t{ 0, 255, 255, 0 }),  // id 0, endless
  };
  for (const vest_packet_t& p : table)
  {
    vest_packet_t q{};
    ASSERT_TRUE(vest_decode(bytes(p).data(), &q)) << int(p.seq);
    EXPECT_TRUE(same(p, q)) << int(p.seq);
  }
  vest_packet_t s = command(42, 0x6, 0, 10, 20, 0);
  s.type = VEST_TYPE_STATUS;
  vest_packet_t q{};
  ASSERT_TRUE(vest_decode(bytes(s).data(), &q));
  EXPECT_TRUE(same(s, q));
}

TEST(VestProtocol, EveryCorruptedByteIsRejected)
{
  // Every byte of the frame replaced by every other value (a 0x00 splits the frame: both halves
  // must be rejected too): nothing decodes, neither whole nor through the streaming parser.
  for (const vest_packet_t& pk : { command(17, 0x9, 180, 0, 0, 60, 300, vest_pattern_t{ 9, 15, 15, 2 }),
                                   command(0, 0x0, 0, 0, 0, 0) })
  {
    const std::vector<uint8_t> good = bytes(pk);
    int tried = 0;
    for (size_t pos = 1; pos + 1 < VEST_PACKET_SIZE; ++pos)
      for (int v = 0; v < 256; ++v)
      {
        if (v == good[pos])
          continue;
        std::vector<uint8_t> bad = good;
        bad[pos] = static_cast<uint8_t>(v);
        vest_packet_t q;
        EXPECT_FALSE(vest_decode(bad.data(), &q)) << "pos " << pos << " value " << v;
        vest_parser_t ps;
        vest_parser_init(&ps);
        EXPECT_TRUE(feedAll(&ps, bad).empty()) << "pos " << pos << " value " << v;
        EXPECT_GE(ps.rejected, 1) << "pos " << pos << " value " << v;
        ++tried;
      }
    EXPECT_EQ(tried, static_cast<int>(VEST_PACKET_SIZE - 2) * 255);
  }
}

TEST(VestProtocol, EveryBitFlipPairIsRejected)
{
  // CRC-32C has Hamming distance 8 at this length: all errors of up to 7 bits in the decoded
  // bytes are caught; here all 2-bit flips of the wire frame (which COBS may turn into more
  // damage) must be rejected.
  const std::vector<uint8_t> good = bytes(command(99, 0xA, 0, 77, 0, 200, 250, vest_pattern_t{ 33, 10, 10, 3 }));
  const size_t bits = (VEST_PACKET_SIZE - 2) * 8;
  for (size_t a = 0; a < bits; ++a)
    for (size_t b = a; b < bits; ++b)
    {
      std::vector<uint8_t> bad = good;
      bad[1 + a / 8] ^= static_cast<uint8_t>(1u << (a % 8));
      if (b != a)
        bad[1 + b / 8] ^= static_cast<uint8_t>(1u << (b % 8));
      vest_parser_t ps;
      vest_parser_init(&ps);
      EXPECT_TRUE(feedAll(&ps, bad).empty()) << a << " " << b;
    }
}

TEST(VestProtocol, BadFieldsAndOtherVersionsRejected)
{
  vest_packet_t q;
  uint8_t version = 0;
  // Valid CRC and framing, illegal field.
  std::vector<uint8_t> f = frameOf({ 2, 0x01, 1, 0x11, 9, 0, 0, 0, 100, 0 });  // reserved motor bit
  EXPECT_EQ(vest_decode_frame(f.data() + 1, static_cast<uint8_t>(f.size() - 2), &q, nullptr), VEST_FRAME_FIELD);
  f = frameOf({ 2, 0x03, 1, 0x01, 9, 0, 0, 0, 100, 0 });  // unknown type
  EXPECT_EQ(vest_decode_frame(f.data() + 1, static_cast<uint8_t>(f.size() - 2), &q, nullptr), VEST_FRAME_FIELD);
  f = frameOf({ 2, 0x01, 1, 0x01, 9, 0, 0, 0, 100 });  // our version, one byte short
  EXPECT_EQ(vest_decode_frame(f.data() + 1, static_cast<uint8_t>(f.size() - 2), &q, nullptr), VEST_FRAME_LENGTH);
  // A version we do not speak (an older one, and a longer future one): rejected, reported with its
  // number. (Version 4 is ours since the pulse patterns; versions 2 and 3 are still decoded.)
  for (const std::vector<uint8_t>& raw :
       { std::vector<uint8_t>{ 1, 0x01, 1, 0x01, 9, 0, 0, 0 },
         std::vector<uint8_t>{ VEST_PROTOCOL_VERSION + 1, 0x01, 1, 0x01, 9, 0, 0, 0, 5, 6, 7 } })
  {
    f = frameOf(raw);
    EXPECT_EQ(vest_decode_frame(f.data() + 1, static_cast<uint8_t>(f.size() - 2), &q, &version),
              VEST_FRAME_VERSION);
    EXPECT_EQ(version, raw[0]);
    vest_firmware_t fw;
    vest_firmware_init(&fw, 0);
    vest_packet_t status;
    int replies = 0;
    for (size_t k = 0; k < f.size(); ++k)
    {
      const int r = vest_firmware_feed(&fw, f[k], 1, &status);
      EXPECT_NE(r, VEST_FEED_APPLIED);
      if (r == VEST_FEED_VERSION_REPLY)
      {
        ++replies;
        EXPECT_EQ(k, f.size() - 1);  // at the frame's end
        EXPECT_EQ(status.type, VEST_TYPE_STATUS);
        std::vector<uint8_t> b(VEST_PACKET_SIZE);
        vest_encode(&status, b.data());
        vest_packet_t back;
        EXPECT_TRUE(vest_decode(b.data(), &back));     // a packet of our version:
        EXPECT_EQ(b[2], VEST_PROTOCOL_VERSION);        // delimiter, COBS code, VERSION
      }
    }
    EXPECT_EQ(replies, 1);
    EXPECT_EQ(fw.parser.version_mismatch, 1);
    EXPECT_EQ(fw.parser.peer_version, raw[0]);
    EXPECT_EQ(fw.duty[0], 0);
  }
  // A version-1 packet (SYNC 0xA5 + CRC-8; its zero bytes split it into frames) is garbage here.
  const std::vector<uint8_t> v1 = { 0xA5, 0x01, 0x07, 0x05, 200, 0, 100, 0, 0x3C };
  vest_parser_t ps;
  vest_parser_init(&ps);
  std::vector<uint8_t> s = { 0 };
  append(&s, v1);
  s.push_back(0);
  EXPECT_TRUE(feedAll(&ps, s).empty());
  EXPECT_GE(ps.rejected, 1);
  EXPECT_EQ(ps.version_mismatch, 0);
}

// Resynchronisation: garbage, a truncated packet and shifted packets in one stream; exactly the
// valid packets come out, in order.
TEST(VestProtocol, ResyncDecodesExactlyTheValidPackets)
{
  std::vector<vest_packet_t> sent;
  std::vector<uint8_t> stream;
  auto good = [&](const vest_packet_t& p) {
    sent.push_back(p);
    append(&stream, bytes(p));
  };
  good(command(1, 0x1, 10, 0, 0, 0));
  // garbage without delimiters, then one with delimiters and old SYNC bytes
  append(&stream, { 0xA5, 0x13, 0xFF, 0x42, 0x07, 0xA5, 0xA5 });
  good(command(2, 0x2, 0, 20, 0, 0));
  append(&stream, { 0x00, 0x05, 0x00, 0xA5, 0x01, 0x02, 0x00, 0x00 });
  good(command(3, 0x4, 0, 0, 30, 0));
  // truncated packet: the first 7 bytes of one, then the next complete packet
  const std::vector<uint8_t> cut = bytes(command(100, 0xF, 255, 255, 255, 255));
  append(&stream, std::vector<uint8_t>(cut.begin(), cut.begin() + 7));
  good(command(4, 0x8, 0, 0, 0, 40));
  // shifted packets: one byte missing at the front of the frame / an extra byte in front of it /
  // the tail of one packet glued to the head of another
  std::vector<uint8_t> sh = bytes(command(101, 0xF, 255, 255, 255, 255));
  append(&stream, { 0x00 });
  append(&stream, std::vector<uint8_t>(sh.begin() + 2, sh.end()));
  good(command(5, 0x3, 50, 50, 0, 0));
  sh = bytes(command(102, 0xF, 255, 255, 255, 255));
  append(&stream, { 0x00, 0x0B });
  append(&stream, std::vector<uint8_t>(sh.begin() + 1, sh.end()));
  good(command(6, 0x1, 60, 0, 0, 0));
  const std::vector<uint8_t> h = bytes(command(103, 0xF, 255, 255, 255, 255));
  const std::vector<uint8_t> t = bytes(command(104, 0xC, 0, 0, 255, 255));
  append(&stream, std::vector<uint8_t>(h.begin(), h.begin() + 6));
  append(&stream, std::vector<uint8_t>(t.begin() + 7, t.end()));
  good(command(7, 0x2, 0, 70, 0, 0));
  // an over-long frame (no delimiter for 100 bytes)
  for (int i = 0; i < 100; ++i)
    stream.push_back(static_cast<uint8_t>(1 + i % 255));
  good(command(8, 0x4, 0, 0, 80, 0));

  vest_parser_t ps;
  vest_parser_init(&ps);
  const std::vector<vest_packet_t> got = feedAll(&ps, stream);
  ASSERT_EQ(got.size(), sent.size());
  for (size_t i = 0; i < sent.size(); ++i)
    EXPECT_TRUE(same(got[i], sent[i])) << i;
  EXPECT_GE(ps.rejected, 7);
  EXPECT_GT(ps.skipped, 100);
}

TEST(VestProtocol, EveryTruncationThenGoodPacket)
{
  // Each prefix of a packet (a link drop mid-packet) followed by a complete one: only the
  // complete one comes out, whatever the prefix length. (Cutting only the trailing delimiter
  // leaves the packet whole: the next leading delimiter ends it.)
  const std::vector<uint8_t> first = bytes(command(1, 0x1, 50, 0, 0, 0));
  const vest_packet_t second = command(2, 0x2, 0, 99, 0, 0);
  for (size_t cut = 1; cut + 1 < VEST_PACKET_SIZE; ++cut)
  {
    vest_parser_t ps;
    vest_parser_init(&ps);
    std::vector<uint8_t> stream(first.begin(), first.begin() + cut);
    append(&stream, bytes(second));
    const std::vector<vest_packet_t> got = feedAll(&ps, stream);
    ASSERT_EQ(got.size(), 1u) << "cut " << cut;
    EXPECT_TRUE(same(got[0], second)) << "cut " << cut;
  }
}

TEST(VestProtocol, ParserRecoversAllPacketsFromGarbage)
{
  std::mt19937 rng(1234);
  std::uniform_int_distribution<int> byte(0, 255), len(0, 40);
  std::vector<uint8_t> stream;
  std::vector<vest_packet_t> sent;
  for (int i = 0; i < 500; ++i)
  {
    const int n = len(rng);
    for (int k = 0; k < n; ++k)
      stream.push_back(static_cast<uint8_t>(k % 7 == 0 ? 0x00 : byte(rng)));  // lots of delimiters
    vest_packet_t p = command(static_cast<uint8_t>(i), static_cast<uint8_t>(byte(rng) & 0xF),
                              static_cast<uint8_t>(byte(rng)), static_cast<uint8_t>(byte(rng)),
                              static_cast<uint8_t>(byte(rng)), static_cast<uint8_t>(byte(rng)));
    const uint8_t on = static_cast<uint8_t>(i % 3 ? byte(rng) : 0);
    p.pattern = vest_pattern_t{ static_cast<uint8_t>(byte(rng)), on, static_cast<uint8_t>(on ? byte(rng) : 0),
                                static_cast<uint8_t>(on ? byte(rng) : 0) };
    sent.push_back(p);
    append(&stream, bytes(p));
  }
  vest_parser_t ps;
  vest_parser_init(&ps);
  const std::vector<vest_packet_t> got = feedAll(&ps, stream);
  ASSERT_EQ(got.size(), sent.size());
  for (size_t i = 0; i < sent.size(); ++i)
    EXPECT_TRUE(same(got[i], sent[i])) << i;
  EXPECT_GT(ps.rejected, 0);
  EXPECT_GT(ps.skipped, 0);
}

TEST(VestFirmware, CommandSetsOutputsAndAnswers)
{
  vest_firmware_t fw;
  vest_firmware_init(&fw, 0);
  for (int i = 0; i < 4; ++i)
    EXPECT_EQ(fw.duty[i], 0);
  // Motor 1's bit is clear: its intensity byte is ignored.
  const std::vector<uint8_t> b = bytes(command(33, 0x5, 200, 123, 40, 0));
  int applied = 0;
  vest_packet_t status{};
  for (uint8_t x : b)
    applied += vest_firmware_feed(&fw, x, 100, &status);
  EXPECT_EQ(applied, 1);
  EXPECT_EQ(fw.duty[0], 200);
  EXPECT_EQ(fw.duty[1], 0);
  EXPECT_EQ(fw.duty[2], 40);
  EXPECT_EQ(fw.duty[3], 0);
  EXPECT_EQ(status.type, VEST_TYPE_STATUS);
  EXPECT_EQ(status.seq, 33);
  EXPECT_EQ(status.motors, 0x5);
  EXPECT_EQ(status.intensity[0], 200);
  EXPECT_EQ(status.intensity[1], 0);
  EXPECT_EQ(status.ttl_ms, 0);
}

// The vest ends a cue by itself when its TTL runs out (the PC may be stalled); the watchdog
// caps a longer TTL.
TEST(VestFirmware, TtlEndsTheCue)
{
  struct Row
  {
    uint16_t ttl;
    uint32_t last_on_ms;  // still on at cmd + this
    int result;           // what the tick one ms later says
  };
  for (const Row& r : { Row{ 120, 120, VEST_TICK_EXPIRED }, Row{ 0, 0, VEST_TICK_EXPIRED },
                        Row{ 499, 499, VEST_TICK_EXPIRED }, Row{ 500, 500, VEST_TICK_WATCHDOG },
                        Row{ 65535, 500, VEST_TICK_WATCHDOG } })
  {
    vest_firmware_t fw;
    vest_firmware_init(&fw, 0);
    vest_packet_t status;
    for (uint8_t x : bytes(command(1, 0x2, 0, 200, 0, 0, r.ttl)))
      vest_firmware_feed(&fw, x, 1000, &status);
    ASSERT_EQ(fw.duty[1], 200) << r.ttl;
    EXPECT_EQ(vest_firmware_tick(&fw, 1000 + r.last_on_ms), VEST_TICK_NONE) << r.ttl;
    EXPECT_EQ(fw.duty[1], 200) << r.ttl;
    EXPECT_EQ(vest_firmware_tick(&fw, 1000 + r.last_on_ms + 1), r.result) << r.ttl;
    EXPECT_EQ(fw.duty[1], 0) << r.ttl;
    EXPECT_EQ(fw.expiries, r.result == VEST_TICK_EXPIRED ? 1 : 0);
    EXPECT_EQ(fw.timeouts, r.result == VEST_TICK_WATCHDOG ? 1 : 0);
  }
  // A newer COMMAND restarts the clock with its own TTL.
  vest_firmware_t fw;
  vest_firmware_init(&fw, 0);
  vest_packet_t status;
  for (uint8_t x : bytes(command(1, 0x1, 90, 0, 0, 0, 100)))
    vest_firmware_feed(&fw, x, 0, &status);
  for (uint8_t x : bytes(command(2, 0x1, 90, 0, 0, 0, 100)))
    vest_firmware_feed(&fw, x, 80, &status);
  EXPECT_EQ(vest_firmware_tick(&fw, 150), VEST_TICK_NONE);
  EXPECT_EQ(fw.duty[0], 90);
  EXPECT_EQ(vest_firmware_tick(&fw, 181), VEST_TICK_EXPIRED);
}

TEST(VestFirmware, IgnoresStatusAndBadPackets)
{
  vest_firmware_t fw;
  vest_firmware_init(&fw, 0);
  vest_packet_t s = command(1, 0xF, 255, 255, 255, 255);
  s.type = VEST_TYPE_STATUS;  // echoed by a loopback: must not drive the motors
  std::vector<uint8_t> stream = bytes(s);
  std::vector<uint8_t> bad = bytes(command(2, 0xF, 255, 255, 255, 255));
  bad[5] ^= 0x10;
  append(&stream, bad);
  vest_packet_t status;
  for (uint8_t x : stream)
    EXPECT_EQ(vest_firmware_feed(&fw, x, 10, &status), 0);
  for (int i = 0; i < 4; ++i)
    EXPECT_EQ(fw.duty[i], 0);
}

TEST(VestFirmware, WatchdogTable)
{
  struct Row
  {
    uint32_t cmd_ms, bad_ms, tick_ms;
    bool on_after;
  };
  // Bad packets (bad_ms) never feed the watchdog; millis() wraps after 2^32 ms.
  const std::vector<Row> rows = { { 1000, 0, 1400, true },  { 1000, 0, 1500, true },
                                  { 1000, 0, 1501, false }, { 1000, 1400, 1600, false },
                                  { 0xFFFFFF00u, 0, 0xF0u, true }, { 0xFFFFFF00u, 0, 0x100u, false } };
  for (const Row& r : rows)
  {
    vest_firmware_t fw;
    vest_firmware_init(&fw, r.cmd_ms);
    vest_packet_t status;
    for (uint8_t x : bytes(command(1, 0x1, 255, 0, 0, 0)))
      vest_firmware_feed(&fw, x, r.cmd_ms, &status);
    ASSERT_EQ(fw.duty[0], 255);
    if (r.bad_ms)
    {
      std::vector<uint8_t> bad = bytes(command(2, 0x1, 255, 0, 0, 0));
      bad[VEST_PACKET_SIZE - 2] ^= 1;
      for (uint8_t x : bad)
        vest_firmware_feed(&fw, x, r.bad_ms, &status);
    }
    const int tripped = vest_firmware_tick(&fw, r.tick_ms);
    EXPECT_EQ(fw.duty[0] > 0, r.on_after) << r.cmd_ms << " -> " << r.tick_ms;
    EXPECT_EQ(tripped == 1, !r.on_after);
    // A tripped watchdog trips once; a running one trips later.
    EXPECT_EQ(vest_firmware_tick(&fw, r.tick_ms + 1000), r.on_after ? 1 : 0);
  }
}

// ---- Protocol version 4: the firmware renders the pulse pattern (issue 33). ----
namespace
{
/// Feeds one COMMAND to the firmware at now_ms; returns the STATUS it answers with.
vest_packet_t feedCommand(vest_firmware_t* fw, const vest_packet_t& p, uint32_t now_ms)
{
  vest_packet_t status{};
  int applied = 0;
  for (uint8_t x : bytes(p))
    applied += vest_firmware_feed(fw, x, now_ms, &status) == VEST_FEED_APPLIED;
  EXPECT_EQ(applied, 1);
  return status;
}

const vest_pattern_t kVeer{ 5, 15, 15, 2 };  // 150 ms on, 150 ms off, x2

bool veerOn(uint32_t t)
{
  return t < 150 || (t >= 300 && t < 450);
}
}  // namespace

// The veer burst, re-sent every 50 ms with the same pattern as the bridge does: on at 0-149 and
// 300-449 ms, off at 150-299 and from 450 ms; the re-sends never restart it; STATUS reports what
// the outputs do at that moment and the pattern playing; tick reports each edge.
TEST(VestFirmware, VeerBurstPulsesAndResendsContinueIt)
{
  const uint32_t t0 = 1000;
  vest_firmware_t fw;
  vest_firmware_init(&fw, 0);
  std::vector<uint32_t> edges;
  for (uint32_t t = 0; t <= 1200; ++t)
  {
    if (t == 0 || t % 50 == 20)  // the start, then a re-send every 50 ms between the edges
    {
      const vest_packet_t st = feedCommand(&fw, command(static_cast<uint8_t>(t / 50), 0x1, 179, 0, 0, 0, 300, kVeer), t0 + t);
      EXPECT_EQ(st.intensity[0], veerOn(t) ? 179 : 0) << t;
      EXPECT_EQ(st.motors, veerOn(t) ? 0x1 : 0x0) << t;
      EXPECT_TRUE(vest_pattern_equal(&st.pattern, &kVeer));
    }
    if (vest_firmware_tick(&fw, t0 + t) == VEST_TICK_PULSE)
      edges.push_back(t);
    ASSERT_EQ(fw.duty[0], veerOn(t) ? 179 : 0) << "t = " << t << " ms";
    ASSERT_EQ(fw.duty[1] | fw.duty[2] | fw.duty[3], 0) << t;
  }
  EXPECT_EQ(edges, (std::vector<uint32_t>{ 150, 300, 450 }));
  EXPECT_EQ(fw.pattern_starts, 1);  // 25 COMMANDs, one start
  EXPECT_EQ(fw.expiries + fw.timeouts, 0);
}

// A new id restarts at phase 0; the same id with another shape is another pattern (restarts);
// a steady pattern is the version-3 behaviour (duties as commanded).
TEST(VestFirmware, NewPatternRestartsSameOneContinues)
{
  const uint32_t t0 = 5000;
  vest_firmware_t fw;
  vest_firmware_init(&fw, 0);
  feedCommand(&fw, command(1, 0x1, 179, 0, 0, 0, 1000, kVeer), t0);
  feedCommand(&fw, command(2, 0x1, 179, 0, 0, 0, 1000, kVeer), t0 + 200);  // same: in its gap
  EXPECT_EQ(fw.duty[0], 0);
  const vest_pattern_t next{ 6, 15, 15, 2 };
  vest_packet_t st = feedCommand(&fw, command(3, 0x1, 179, 0, 0, 0, 1000, next), t0 + 200);  // new id: on now
  EXPECT_EQ(fw.duty[0], 179);
  EXPECT_EQ(st.intensity[0], 179);
  EXPECT_EQ(st.pattern.id, 6);
  for (uint32_t t = 200; t < 900; ++t)
  {
    if (t % 50 == 0)
      feedCommand(&fw, command(4, 0x1, 179, 0, 0, 0, 1000, next), t0 + t);
    vest_firmware_tick(&fw, t0 + t);
    ASSERT_EQ(fw.duty[0], veerOn(t - 200) ? 179 : 0) << t;
  }
  EXPECT_EQ(fw.pattern_starts, 2);
  // Same id, another shape: a new pattern (restarts), not a continuation.
  const vest_pattern_t reshaped{ 6, 15, 15, 3 };
  feedCommand(&fw, command(5, 0x1, 179, 0, 0, 0, 1000, reshaped), t0 + 900);
  EXPECT_EQ(fw.duty[0], 179);
  EXPECT_EQ(fw.pattern_starts, 3);
  // The duties follow every COMMAND while the pattern runs (the same pattern, other duties).
  feedCommand(&fw, command(6, 0x3, 255, 90, 0, 0, 1000, reshaped), t0 + 950);
  EXPECT_EQ(fw.duty[0], 255);
  EXPECT_EQ(fw.duty[1], 90);
  EXPECT_EQ(fw.pattern_starts, 3);
  // Steady (ON 0): on all the time, like version 3.
  feedCommand(&fw, command(7, 0x4, 0, 0, 120, 0, 400, vest_pattern_t{ 8, 0, 0, 0 }), t0 + 1000);
  for (uint32_t t = 1000; t <= 1400; ++t)
  {
    EXPECT_EQ(vest_firmware_tick(&fw, t0 + t), VEST_TICK_NONE) << t;
    ASSERT_EQ(fw.duty[2], 120) << t;
  }
  EXPECT_EQ(vest_firmware_tick(&fw, t0 + 1401), VEST_TICK_EXPIRED);
}

// TTL and watchdog still switch everything off, mid-pulse; the same pattern coming back
// continues where its clock stands (never replays a burst); the walk-on tick and the unsure
// pattern are timed exactly.
TEST(VestFirmware, TtlAndWatchdogCutThePattern)
{
  const uint32_t t0 = 100;
  // TTL 100 ms cuts the first veer pulse at 101 ms.
  vest_firmware_t fw;
  vest_firmware_init(&fw, 0);
  feedCommand(&fw, command(1, 0x1, 179, 0, 0, 0, 100, kVeer), t0);
  EXPECT_EQ(vest_firmware_tick(&fw, t0 + 100), VEST_TICK_NONE);
  EXPECT_EQ(fw.duty[0], 179);
  EXPECT_EQ(vest_firmware_tick(&fw, t0 + 101), VEST_TICK_EXPIRED);
  EXPECT_EQ(fw.duty[0], 0);
  for (uint32_t t = 102; t < 320; ++t)
    ASSERT_EQ(vest_firmware_tick(&fw, t0 + t) == VEST_TICK_NONE && fw.duty[0] == 0, true) << t;
  // The same pattern again at 320 ms: its second pulse, from its own clock (on until 449).
  feedCommand(&fw, command(2, 0x1, 179, 0, 0, 0, 300, kVeer), t0 + 320);
  EXPECT_EQ(fw.duty[0], 179);
  EXPECT_EQ(vest_firmware_tick(&fw, t0 + 449), VEST_TICK_NONE);
  EXPECT_EQ(vest_firmware_tick(&fw, t0 + 450), VEST_TICK_PULSE);
  EXPECT_EQ(fw.duty[0], 0);
  // ... and again at 700 ms: the burst is over, nothing replays.
  feedCommand(&fw, command(3, 0x1, 179, 0, 0, 0, 300, kVeer), t0 + 700);
  for (uint32_t t = 700; t < 1000; ++t)
  {
    vest_firmware_tick(&fw, t0 + t);
    ASSERT_EQ(fw.duty[0], 0) << t;
  }
  EXPECT_EQ(fw.pattern_starts, 1);

  // Watchdog (TTL beyond it): endless pulses 100 ms on / 50 ms off, one COMMAND, off at 501 ms in
  // the middle of a pulse (the fourth runs 450-549).
  vest_firmware_t wd;
  vest_firmware_init(&wd, t0);
  feedCommand(&wd, command(1, 0xC, 0, 0, 255, 255, 65535, vest_pattern_t{ 9, 10, 5, 0 }), t0);
  std::vector<uint32_t> pulse_edges;
  int r = VEST_TICK_NONE;
  uint32_t t = 1;
  for (; t <= 600; ++t)
  {
    r = vest_firmware_tick(&wd, t0 + t);
    if (r == VEST_TICK_PULSE)
      pulse_edges.push_back(t);
    if (r == VEST_TICK_WATCHDOG)
      break;
    ASSERT_EQ(wd.duty[2], (t % 150) < 100 ? 255 : 0) << t;
  }
  EXPECT_EQ(r, VEST_TICK_WATCHDOG);
  EXPECT_EQ(t, 501u);
  EXPECT_EQ(wd.duty[2] | wd.duty[3], 0);
  EXPECT_EQ(pulse_edges, (std::vector<uint32_t>{ 100, 150, 250, 300, 400, 450 }));
  EXPECT_EQ(wd.timeouts, 1);

  // The walk-on tick (both shoulders, 100 ms once) and the unsure pattern (both waist motors,
  // 100 / 100 ms x3), re-sent every 50 ms.
  struct Case
  {
    vest_pattern_t p;
    uint8_t motors;
    std::function<bool(uint32_t)> on;
  };
  for (const Case& c : { Case{ { 11, 10, 0, 1 }, 0x3, [](uint32_t t) { return t < 100; } },
                         Case{ { 12, 10, 10, 3 }, 0xC, [](uint32_t t) { return t < 500 && (t % 200) < 100; } } })
  {
    vest_firmware_t f;
    vest_firmware_init(&f, 0);
    for (uint32_t u = 0; u < 1500; ++u)
    {
      if (u % 50 == 0)
        feedCommand(&f, command(1, c.motors, 179, 179, 255, 255, 300, c.p), 7000 + u);
      vest_firmware_tick(&f, 7000 + u);
      ASSERT_EQ(f.motors, c.on(u) ? c.motors : 0) << int(c.p.id) << " at " << u;
    }
  }
}

// millis() wraps after 49.7 days: a pattern running across the wrap keeps its phase, and a
// burst that is over stays over (no replay 2^32 ms later).
TEST(VestFirmware, PatternAcrossTheMillisWrap)
{
  const uint32_t t0 = 0xFFFFFF00u;  // 256 ms before the wrap
  vest_firmware_t fw;
  vest_firmware_init(&fw, t0);
  for (uint32_t t = 0; t < 1000; ++t)
  {
    if (t % 50 == 0)
      feedCommand(&fw, command(1, 0x2, 0, 200, 0, 0, 300, kVeer), t0 + t);
    vest_firmware_tick(&fw, t0 + t);
    ASSERT_EQ(fw.duty[1], veerOn(t) ? 200 : 0) << t;
  }
  EXPECT_TRUE(fw.pattern_over);
  // The same pattern much later (its clock would have wrapped back to phase 0): still over.
  fw.pattern_start_ms = 5u;  // as if 2^32 ms had passed since it started
  feedCommand(&fw, command(2, 0x2, 0, 200, 0, 0, 300, kVeer), 5u);
  EXPECT_EQ(fw.duty[1], 0);
}

// When the outputs change next by themselves: what the simulated vest sleeps until.
TEST(VestFirmware, NextChangeTable)
{
  vest_firmware_t fw;
  vest_firmware_init(&fw, 0);
  EXPECT_EQ(vest_firmware_next_change_ms(&fw, 10), VEST_NEVER);  // no COMMAND: nothing due
  feedCommand(&fw, command(1, 0x1, 179, 0, 0, 0, 400, kVeer), 1000);
  EXPECT_EQ(vest_firmware_next_change_ms(&fw, 1000), 150u);  // the first pulse ends
  EXPECT_EQ(vest_firmware_next_change_ms(&fw, 1200), 100u);  // the second begins
  EXPECT_EQ(vest_firmware_next_change_ms(&fw, 1350), 51u);   // TTL (off at 401 ms) before the edge at 450
  feedCommand(&fw, command(2, 0x1, 179, 0, 0, 0, 400, vest_pattern_t{ 9, 0, 0, 0 }), 2000);
  EXPECT_EQ(vest_firmware_next_change_ms(&fw, 2000), 401u);  // steady: the TTL only
  feedCommand(&fw, command(3, 0x1, 179, 0, 0, 0, 65535, vest_pattern_t{ 9, 0, 0, 0 }), 3000);
  EXPECT_EQ(vest_firmware_next_change_ms(&fw, 3100), 401u);  // the watchdog
}

// A version-3 bridge's COMMAND (no pattern bytes): obeyed steady, answered in version 3 with the
// 17-byte STATUS it can read.
TEST(VestFirmware, Version3BridgeDrivenSteady)
{
  vest_firmware_t fw;
  vest_firmware_init(&fw, 0);
  const vest_packet_t p = command(4, 0x1, 200, 0, 0, 0, 300);
  std::vector<uint8_t> b(VEST_PACKET_SIZE);
  b.resize(vest_encode_version(&p, 3, b.data()));
  ASSERT_EQ(b.size(), 17u);
  vest_packet_t status{};
  int applied = 0;
  for (uint8_t byte : b)
    applied += vest_firmware_feed(&fw, byte, 10, &status) == VEST_FEED_APPLIED;
  EXPECT_EQ(applied, 1);
  EXPECT_EQ(fw.reply_version, 3);
  for (uint32_t t = 10; t <= 310; ++t)
  {
    vest_firmware_tick(&fw, t);
    ASSERT_EQ(fw.duty[0], 200) << t;
  }
  std::vector<uint8_t> out(VEST_PACKET_SIZE);
  out.resize(vest_encode_version(&status, fw.reply_version, out.data()));
  ASSERT_EQ(out.size(), 17u);
  vest_packet_t back{};
  uint8_t version = 0;
  ASSERT_EQ(vest_decode_frame(out.data() + 1, static_cast<uint8_t>(out.size() - 2), &back, &version), VEST_FRAME_OK);
  EXPECT_EQ(version, 3);
  EXPECT_EQ(back.type, VEST_TYPE_STATUS);
  EXPECT_EQ(back.intensity[0], 200);
  EXPECT_EQ(vest_firmware_sensor_version(&fw), 3);  // its RANGE / BUTTONS in version 3
}

// ---- Protocol version 3: RANGE and BUTTONS (issue 20, issue 24), version-2 peers. ----

extern "C" int assistive_tactile_protocol_c_check(void);
extern "C" int assistive_tactile_protocol_c_check_v3(void);
extern "C" int assistive_tactile_protocol_c_check_v5(void);

TEST(VestProtocol, CRoundTrip)
{
  // protocol_c_check.c, compiled as C99: COMMAND, RANGE, BUTTONS and IMU round trips.
  EXPECT_EQ(assistive_tactile_protocol_c_check(), 1);
  EXPECT_EQ(assistive_tactile_protocol_c_check_v3(), 1);
  EXPECT_EQ(assistive_tactile_protocol_c_check_v5(), 1);
}

TEST(VestProtocol, RangeAndButtonsRoundTrip)
{
  vest_parser_t ps;
  vest_parser_init(&ps);
  for (const vest_range_t& r : { vest_range_t{ 0, VEST_RANGE_OK, 200, 3 }, vest_range_t{ 255, VEST_RANGE_OK, 4000, 2 },
                                 vest_range_t{ 17, VEST_RANGE_NO_ECHO, 0, 1 },
                                 vest_range_t{ 18, VEST_RANGE_SENSOR_MISSING, 0, 0 } })
  {
    std::vector<uint8_t> b(VEST_RANGE_PACKET_SIZE);
    vest_encode_range(&r, b.data());
    EXPECT_EQ(b.front(), 0);
    EXPECT_EQ(b.back(), 0);
    for (size_t i = 1; i + 1 < b.size(); ++i) EXPECT_NE(b[i], 0);
    vest_message_t m;
    uint8_t version = 0;
    ASSERT_EQ(vest_decode_message(b.data() + 1, static_cast<uint8_t>(b.size() - 2), &m, &version), VEST_FRAME_OK);
    EXPECT_EQ(version, VEST_PROTOCOL_VERSION);
    EXPECT_EQ(m.type, VEST_TYPE_RANGE);
    EXPECT_EQ(m.range.seq, r.seq);
    EXPECT_EQ(m.range.status, r.status);
    EXPECT_EQ(m.range.range_mm, r.range_mm);
    EXPECT_EQ(m.range.echoes, r.echoes);
    // Not a COMMAND / STATUS: the motor-side decoders do not take it.
    vest_packet_t p;
    EXPECT_EQ(vest_decode_frame(b.data() + 1, static_cast<uint8_t>(b.size() - 2), &p, nullptr), VEST_FRAME_OTHER_TYPE);
    int got = 0;
    for (uint8_t byte : b)
      got += vest_parser_feed_message(&ps, byte, &m);
    EXPECT_EQ(got, 1);
  }
  const vest_buttons_t bt{ 200, 0x3, 255, 0, 7, 1 };
  std::vector<uint8_t> b(VEST_BUTTONS_PACKET_SIZE);
  vest_encode_buttons(&bt, b.data());
  vest_message_t m;
  ASSERT_EQ(vest_decode_message(b.data() + 1, static_cast<uint8_t>(b.size() - 2), &m, nullptr), VEST_FRAME_OK);
  EXPECT_EQ(m.type, VEST_TYPE_BUTTONS);
  EXPECT_EQ(m.buttons.seq, 200);
  EXPECT_EQ(m.buttons.held, 3);
  EXPECT_EQ(m.buttons.short_a, 255);
  EXPECT_EQ(m.buttons.long_a, 0);
  EXPECT_EQ(m.buttons.short_b, 7);
  EXPECT_EQ(m.buttons.long_b, 1);
  // A motor-only parser counts it as a valid packet and hands nothing on.
  vest_parser_t motor;
  vest_parser_init(&motor);
  EXPECT_TRUE(feedAll(&motor, b).empty());
  EXPECT_EQ(motor.packets, 1);
  EXPECT_EQ(motor.rejected, 0);
}

TEST(VestProtocol, RangeAndButtonsBadInputRejected)
{
  vest_message_t m;
  // Every single-bit error of a RANGE frame is caught (CRC-32C).
  const vest_range_t r{ 5, VEST_RANGE_OK, 1500, 3 };
  std::vector<uint8_t> good(VEST_RANGE_PACKET_SIZE);
  vest_encode_range(&r, good.data());
  for (size_t bit = 0; bit < (good.size() - 2) * 8; ++bit)
  {
    std::vector<uint8_t> bad = good;
    bad[1 + bit / 8] ^= static_cast<uint8_t>(1u << (bit % 8));
    vest_parser_t ps;
    vest_parser_init(&ps);
    int got = 0;
    for (uint8_t byte : bad) got += vest_parser_feed_message(&ps, byte, &m);
    EXPECT_EQ(got, 0) << bit;
  }
  auto decode = [&](const std::vector<uint8_t>& raw) {
    const std::vector<uint8_t> f = frameOf(raw);
    return vest_decode_message(f.data() + 1, static_cast<uint8_t>(f.size() - 2), &m, nullptr);
  };
  const uint8_t V = VEST_PROTOCOL_VERSION;
  EXPECT_EQ(decode({ V, 0x03, 1, 0, 0xDC, 0x05, 3 }), VEST_FRAME_OK);
  EXPECT_EQ(decode({ V, 0x03, 1, 3, 0, 0, 0 }), VEST_FRAME_FIELD);         // unknown status
  EXPECT_EQ(decode({ V, 0x03, 1, 0, 0xDC, 0x05, 4 }), VEST_FRAME_FIELD);   // 4 echoes of 3 pings
  EXPECT_EQ(decode({ V, 0x03, 1, 0, 0xDC, 0x05, 1 }), VEST_FRAME_FIELD);   // OK from one echo
  EXPECT_EQ(decode({ V, 0x03, 1, 1, 0xDC, 0x05, 1 }), VEST_FRAME_FIELD);   // no echo with a range
  EXPECT_EQ(decode({ V, 0x03, 1, 0, 0xDC, 0x05 }), VEST_FRAME_LENGTH);     // one byte short
  EXPECT_EQ(decode({ V, 0x04, 1, 0x04, 0, 0, 0, 0 }), VEST_FRAME_FIELD);   // a third button
  EXPECT_EQ(decode({ V, 0x04, 1, 0x01, 0, 0, 0, 0, 0 }), VEST_FRAME_LENGTH);
  EXPECT_EQ(decode({ 2, 0x03, 1, 0, 0xDC, 0x05, 3 }), VEST_FRAME_FIELD);   // no RANGE in version 2
  EXPECT_EQ(decode({ 2, 0x04, 1, 0x01, 0, 0, 0, 0 }), VEST_FRAME_FIELD);
}

TEST(VestProtocol, RangerMedianOfThreePings)
{
  uint16_t mm = 0;
  // 343 m/s: 1 m is a 5831 us round trip.
  EXPECT_EQ(vest_classify_ping(1, 1, 5831, &mm), VEST_PING_ECHO);
  EXPECT_EQ(mm, 1000);
  EXPECT_EQ(vest_echo_us_to_mm(1166), 200);
  EXPECT_EQ(vest_classify_ping(1, 1, 38000, &mm), VEST_PING_NO_ECHO);  // the sensor's "nothing" pulse
  EXPECT_EQ(vest_classify_ping(1, 1, 24000, &mm), VEST_PING_NO_ECHO);  // beyond 4 m
  EXPECT_EQ(vest_classify_ping(1, 0, 0, &mm), VEST_PING_NO_ECHO);      // never fell
  EXPECT_EQ(vest_classify_ping(0, 0, 0, &mm), VEST_PING_MISSING);      // never rose
  EXPECT_EQ(mm, 0);

  vest_ranger_t rg{};
  vest_range_t out{};
  EXPECT_EQ(vest_ranger_ping(&rg, VEST_PING_ECHO, 1000, &out), 0);  // 3 pings first
  EXPECT_EQ(vest_ranger_ping(&rg, VEST_PING_ECHO, 3000, &out), 0);
  ASSERT_EQ(vest_ranger_ping(&rg, VEST_PING_ECHO, 1100, &out), 1);
  EXPECT_EQ(out.status, VEST_RANGE_OK);
  EXPECT_EQ(out.range_mm, 1100);  // the outlier 3000 is voted out
  EXPECT_EQ(out.echoes, 3);
  EXPECT_EQ(out.seq, 0);
  ASSERT_EQ(vest_ranger_ping(&rg, VEST_PING_NO_ECHO, 0, &out), 1);  // 3000, 1100, none
  EXPECT_EQ(out.status, VEST_RANGE_OK);
  EXPECT_EQ(out.range_mm, 3000);  // two echoes: the farther (a missing echo counts as farthest)
  EXPECT_EQ(out.seq, 1);
  ASSERT_EQ(vest_ranger_ping(&rg, VEST_PING_NO_ECHO, 0, &out), 1);  // 1100, none, none
  EXPECT_EQ(out.status, VEST_RANGE_NO_ECHO);
  EXPECT_EQ(out.range_mm, 0);
  EXPECT_EQ(out.echoes, 1);
  ASSERT_EQ(vest_ranger_ping(&rg, VEST_PING_MISSING, 0, &out), 1);  // none, none, missing
  EXPECT_EQ(out.status, VEST_RANGE_NO_ECHO);
  ASSERT_EQ(vest_ranger_ping(&rg, VEST_PING_MISSING, 0, &out), 1);  // none, missing, missing
  EXPECT_EQ(out.status, VEST_RANGE_SENSOR_MISSING);
}

TEST(VestProtocol, ButtonsDebouncedShortAndLong)
{
  vest_button_t b{};
  // A 10 ms bounce is not a press.
  EXPECT_EQ(vest_button_update(&b, 1, 1000), VEST_PRESS_NONE);
  EXPECT_EQ(vest_button_update(&b, 0, 1010), VEST_PRESS_NONE);
  EXPECT_EQ(vest_button_update(&b, 0, 1100), VEST_PRESS_NONE);
  EXPECT_EQ(b.stable, 0);
  // Down 200 ms (bouncing at first): one SHORT, at the release.
  EXPECT_EQ(vest_button_update(&b, 1, 2000), VEST_PRESS_NONE);
  EXPECT_EQ(vest_button_update(&b, 0, 2005), VEST_PRESS_NONE);
  EXPECT_EQ(vest_button_update(&b, 1, 2010), VEST_PRESS_NONE);
  EXPECT_EQ(vest_button_update(&b, 1, 2040), VEST_PRESS_NONE);
  EXPECT_EQ(b.stable, 1);
  EXPECT_EQ(vest_button_update(&b, 1, 2200), VEST_PRESS_NONE);
  EXPECT_EQ(vest_button_update(&b, 0, 2210), VEST_PRESS_NONE);
  EXPECT_EQ(vest_button_update(&b, 0, 2240), VEST_PRESS_SHORT);
  EXPECT_EQ(vest_button_update(&b, 0, 2300), VEST_PRESS_NONE);
  // Held 1.5 s: LONG once, while held (at 1 s), nothing at the release.
  int longs = 0, shorts = 0;
  for (uint32_t t = 3000; t <= 4500; t += 10)
  {
    const int r = vest_button_update(&b, 1, t);
    longs += r == VEST_PRESS_LONG;
    shorts += r == VEST_PRESS_SHORT;
    if (r == VEST_PRESS_LONG)
    {
      EXPECT_EQ(t, 3030u + VEST_LONG_PRESS_MS);
    }
  }
  for (uint32_t t = 4510; t <= 4600; t += 10) shorts += vest_button_update(&b, 0, t) == VEST_PRESS_SHORT;
  EXPECT_EQ(longs, 1);
  EXPECT_EQ(shorts, 0);
}

// The IMU's windows: the mean of the readings of each 20 ms (rounded half away from zero,
// saturated), SENSOR_MISSING when none could be read, and packets only to a version-5 bridge.
TEST(VestFirmware, ImuWindowMeansOnlyToVersion5)
{
  vest_firmware_t fw;
  vest_firmware_init(&fw, 1000);
  vest_imu_t out{};
  vest_packet_t status;
  const int16_t g[3] = { 100, -3, 20 }, a[3] = { 0, 0, 9807 };
  const int16_t g2[3] = { 101, -4, 32767 }, a2[3] = { 1, -1, 32767 };
  // Nobody spoke yet (and then a version-4 bridge): the windows run, nothing goes out.
  for (uint32_t t = 1005; t <= 1040; t += 5)
    EXPECT_EQ(vest_firmware_imu(&fw, 1, g, a, t, &out), 0) << t;
  for (uint8_t byte : bytesV4(command(1, 0x1, 9, 0, 0, 0, 300)))
    vest_firmware_feed(&fw, byte, 1041, &status);
  EXPECT_EQ(fw.peer_version, 4);
  for (uint32_t t = 1045; t <= 1060; t += 5)
    EXPECT_EQ(vest_firmware_imu(&fw, 1, g, a, t, &out), 0) << t;
  // A version-5 bridge: a packet every 20 ms.
  for (uint8_t byte : bytes(command(2, 0x1, 9, 0, 0, 0, 300)))
    vest_firmware_feed(&fw, byte, 1061, &status);
  EXPECT_EQ(fw.peer_version, 5);
  EXPECT_EQ(vest_firmware_imu(&fw, 1, g, a, 1065, &out), 0);
  EXPECT_EQ(vest_firmware_imu(&fw, 1, g2, a2, 1070, &out), 0);
  EXPECT_EQ(vest_firmware_imu(&fw, 1, g2, a2, 1075, &out), 0);
  ASSERT_EQ(vest_firmware_imu(&fw, 1, g2, a2, 1080, &out), 1);
  EXPECT_EQ(out.status, VEST_IMU_OK);
  EXPECT_EQ(out.samples, 4);
  EXPECT_EQ(out.t_ms, 1080);
  EXPECT_EQ(out.gyro[0], 101);     // 403 / 4 = 100.75
  EXPECT_EQ(out.gyro[1], -4);      // -15 / 4 = -3.75
  EXPECT_EQ(out.gyro[2], 24580);   // (20 + 3 * 32767) / 4 = 24580.25
  EXPECT_EQ(out.accel[0], 1);      // 3 / 4 = 0.75
  EXPECT_EQ(out.accel[1], -1);     // -3 / 4
  EXPECT_EQ(out.accel[2], 27027);  // (9807 + 3 * 32767) / 4
  const uint8_t seq = out.seq;
  // A window with no reading: SENSOR_MISSING, zeros.
  for (uint32_t t = 1085; t < 1100; t += 5)
    EXPECT_EQ(vest_firmware_imu(&fw, 0, g, a, t, &out), 0);
  ASSERT_EQ(vest_firmware_imu(&fw, 0, g, a, 1100, &out), 1);
  EXPECT_EQ(out.status, VEST_IMU_SENSOR_MISSING);
  EXPECT_EQ(out.samples, 0);
  EXPECT_EQ(out.gyro[0], 0);
  EXPECT_EQ(out.accel[2], 0);
  EXPECT_EQ(out.seq, static_cast<uint8_t>(seq + 1));
  // Encoded, it decodes (the encoder writes only legal packets).
  std::vector<uint8_t> b(VEST_IMU_PACKET_SIZE);
  vest_encode_imu_version(&out, vest_firmware_sensor_version(&fw), b.data());
  vest_message_t m;
  EXPECT_EQ(vest_decode_message(b.data() + 1, static_cast<uint8_t>(b.size() - 2), &m, nullptr), VEST_FRAME_OK);
  // Saturation at the int16 range's ends.
  EXPECT_EQ(vest_mean16(-40000, 1), -32767);
  EXPECT_EQ(vest_mean16(40000, 1), 32767);
  EXPECT_EQ(vest_mean16(-5, 2), -3);  // -2.5: half away from zero
}

TEST(VestProtocol, FirmwareSpeaksVersion2ToAnOldBridgeAndSensorsOnlyToVersion3)
{
  vest_firmware_t fw;
  vest_firmware_init(&fw, 0);
  vest_packet_t status;
  vest_range_t range;
  vest_buttons_t buttons;
  // An old (version 2) bridge: its COMMAND is obeyed and answered in version 2; no RANGE/BUTTONS.
  const vest_packet_t p = command(4, 0x1, 200, 0, 0, 0, 300);
  std::vector<uint8_t> b(VEST_PACKET_SIZE);
  vest_encode_version(&p, 2, b.data());
  int applied = 0;
  for (uint8_t byte : b) applied += vest_firmware_feed(&fw, byte, 10, &status) == VEST_FEED_APPLIED;
  EXPECT_EQ(applied, 1);
  EXPECT_EQ(fw.duty[0], 200);
  EXPECT_EQ(fw.reply_version, 2);
  EXPECT_EQ(fw.parser.version_mismatch, 0);
  for (int i = 0; i < 3; ++i) EXPECT_EQ(vest_firmware_range(&fw, VEST_PING_ECHO, 1000, &range), 0);
  EXPECT_EQ(vest_firmware_buttons(&fw, 1, 0, 2000, &buttons), 0);
  // A version-3 bridge: answered in version 3, sensors go out.
  vest_encode(&p, b.data());
  applied = 0;
  for (uint8_t byte : b) applied += vest_firmware_feed(&fw, byte, 2100, &status) == VEST_FEED_APPLIED;
  EXPECT_EQ(applied, 1);
  EXPECT_EQ(fw.reply_version, VEST_PROTOCOL_VERSION);
  ASSERT_EQ(vest_firmware_range(&fw, VEST_PING_ECHO, 1000, &range), 1);
  EXPECT_EQ(range.range_mm, 1000);
  // Buttons: a change of HELD, a SHORT, the heartbeat.
  ASSERT_EQ(vest_firmware_buttons(&fw, 1, 0, 2200, &buttons), 1);  // A down since 2000 (debounced at 2030)
  EXPECT_EQ(buttons.held, 1);
  EXPECT_EQ(vest_firmware_buttons(&fw, 0, 0, 2300, &buttons), 0);  // bouncing? not yet stable
  ASSERT_EQ(vest_firmware_buttons(&fw, 0, 0, 2340, &buttons), 1);
  EXPECT_EQ(buttons.held, 0);
  EXPECT_EQ(buttons.short_a, 1);
  EXPECT_EQ(buttons.long_a, 0);
  EXPECT_EQ(vest_firmware_buttons(&fw, 0, 0, 3000, &buttons), 0);
  ASSERT_EQ(vest_firmware_buttons(&fw, 0, 0, 3340, &buttons), 1);  // heartbeat, 1 s after the last
  EXPECT_EQ(buttons.short_a, 1);
}
