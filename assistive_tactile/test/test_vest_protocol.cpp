// The packet codec, the streaming parser and the firmware behaviour of vest_protocol.h (the code
// the Arduino sketch runs, compiled here on the host).
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "assistive_tactile/vest_protocol.h"

namespace
{
vest_packet_t command(uint8_t seq, uint8_t motors, uint8_t i0, uint8_t i1, uint8_t i2, uint8_t i3)
{
  vest_packet_t p{};
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

bool same(const vest_packet_t& a, const vest_packet_t& b)
{
  return a.type == b.type && a.seq == b.seq && a.motors == b.motors &&
         std::equal(a.intensity, a.intensity + 4, b.intensity);
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
}  // namespace

TEST(VestProtocol, Crc8CheckValue)
{
  // CRC-8/SMBUS (poly 0x07, init 0) catalogue check value.
  const uint8_t msg[] = { '1', '2', '3', '4', '5', '6', '7', '8', '9' };
  EXPECT_EQ(vest_crc8(msg, 9), 0xF4);
  EXPECT_EQ(vest_crc8(msg, 0), 0x00);
}

TEST(VestProtocol, KnownEncoding)
{
  const std::vector<uint8_t> b = bytes(command(7, 0x5, 200, 0, 100, 0));
  const std::vector<uint8_t> head = { 0xA5, 0x01, 0x07, 0x05, 200, 0, 100, 0 };
  EXPECT_TRUE(std::equal(head.begin(), head.end(), b.begin()));
  EXPECT_EQ(b[8], vest_crc8(b.data() + 1, 7));
}

TEST(VestProtocol, RoundTripTable)
{
  const std::vector<vest_packet_t> table = {
    command(0, 0x0, 0, 0, 0, 0),       command(1, 0x1, 255, 0, 0, 0),   command(2, 0x2, 0, 128, 0, 0),
    command(3, 0x4, 0, 0, 1, 0),       command(4, 0x8, 0, 0, 0, 77),    command(255, 0xF, 255, 255, 255, 255),
    command(9, 0x3, 0xA5, 0xA5, 0, 0),  // SYNC values inside the payload
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
  const std::vector<uint8_t> good = bytes(command(17, 0x9, 180, 0, 0, 60));
  int tried = 0;
  for (size_t pos = 0; pos < VEST_PACKET_SIZE; ++pos)
    for (int v = 0; v < 256; ++v)
    {
      if (v == good[pos])
        continue;
      std::vector<uint8_t> bad = good;
      bad[pos] = static_cast<uint8_t>(v);
      vest_packet_t q;
      EXPECT_FALSE(vest_decode(bad.data(), &q)) << "pos " << pos << " value " << v;
      ++tried;
    }
  EXPECT_EQ(tried, 9 * 255);
}

TEST(VestProtocol, ReservedBitsAndUnknownTypeRejected)
{
  std::vector<uint8_t> b = bytes(command(1, 0x1, 9, 0, 0, 0));
  b[3] = 0x11;
  b[8] = vest_crc8(b.data() + 1, 7);  // valid CRC, invalid field
  vest_packet_t q;
  EXPECT_FALSE(vest_decode(b.data(), &q));
  b = bytes(command(1, 0x1, 9, 0, 0, 0));
  b[1] = 0x03;
  b[8] = vest_crc8(b.data() + 1, 7);
  EXPECT_FALSE(vest_decode(b.data(), &q));
}

TEST(VestProtocol, ParserTruncatedPacketThenGoodOne)
{
  // Each prefix of a packet (a link drop mid-packet) followed by a complete one: only the
  // complete one comes out, whatever the prefix length.
  const std::vector<uint8_t> first = bytes(command(1, 0x1, 50, 0, 0, 0));
  const vest_packet_t second = command(2, 0x2, 0, 99, 0, 0);
  for (size_t cut = 1; cut < VEST_PACKET_SIZE; ++cut)
  {
    vest_parser_t ps;
    vest_parser_init(&ps);
    std::vector<uint8_t> stream(first.begin(), first.begin() + cut);
    const std::vector<uint8_t> b2 = bytes(second);
    stream.insert(stream.end(), b2.begin(), b2.end());
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
      stream.push_back(static_cast<uint8_t>(k % 7 == 0 ? VEST_SYNC : byte(rng)));  // lots of false SYNCs
    vest_packet_t p = command(static_cast<uint8_t>(i), static_cast<uint8_t>(byte(rng) & 0xF),
                              static_cast<uint8_t>(byte(rng)), static_cast<uint8_t>(byte(rng)),
                              static_cast<uint8_t>(byte(rng)), static_cast<uint8_t>(byte(rng)));
    sent.push_back(p);
    const std::vector<uint8_t> b = bytes(p);
    stream.insert(stream.end(), b.begin(), b.end());
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
  stream.insert(stream.end(), bad.begin(), bad.end());
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
      bad[8] ^= 1;
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
