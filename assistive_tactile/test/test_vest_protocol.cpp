// The packet codec, the COBS framing, the streaming parser and the firmware behaviour of
// vest_protocol.h (the code the Arduino sketch runs, compiled here on the host).
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "assistive_tactile/vest_protocol.h"

namespace
{
vest_packet_t command(uint8_t seq, uint8_t motors, uint8_t i0, uint8_t i1, uint8_t i2, uint8_t i3,
                      uint16_t ttl_ms = 1000)
{
  vest_packet_t p{};
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

TEST(VestProtocol, KnownEncoding)
{
  // seq 7, motors 0x5, duties 200 0 100 0, TTL 300 ms:
  // raw 02 01 07 05 C8 00 64 00 2C 01 CRC(4 bytes, low first).
  const std::vector<uint8_t> raw = { 0x02, 0x01, 0x07, 0x05, 200, 0, 100, 0, 0x2C, 0x01 };
  const uint32_t crc = vest_crc32c(raw.data(), 10);
  std::vector<uint8_t> want = { 0x00, 0x06, 0x02, 0x01, 0x07, 0x05, 200, 0x02, 100, 0x07, 0x2C, 0x01 };
  // TTL and CRC bytes (none is 0 here: checked) close the last COBS group.
  for (int k = 0; k < 4; ++k)
    ASSERT_NE((crc >> (8 * k)) & 0xFF, 0u) << k;
  for (int k = 0; k < 4; ++k)
    want.push_back(static_cast<uint8_t>(crc >> (8 * k)));
  want.push_back(0x00);
  EXPECT_EQ(bytes(command(7, 0x5, 200, 0, 100, 0, 300)), want);
  EXPECT_EQ(want.size(), VEST_PACKET_SIZE);
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
  for (const vest_packet_t& pk : { command(17, 0x9, 180, 0, 0, 60), command(0, 0x0, 0, 0, 0, 0) })
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
    EXPECT_EQ(tried, 15 * 255);
  }
}

TEST(VestProtocol, EveryBitFlipPairIsRejected)
{
  // CRC-32C has Hamming distance 8 at this length: all errors of up to 7 bits in the decoded
  // bytes are caught; here all 2-bit flips of the wire frame (which COBS may turn into more
  // damage) must be rejected.
  const std::vector<uint8_t> good = bytes(command(99, 0xA, 0, 77, 0, 200));
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
  // Another version (same layout, and a longer future one): rejected, reported with its number.
  for (const std::vector<uint8_t>& raw : { std::vector<uint8_t>{ 1, 0x01, 1, 0x01, 9, 0, 0, 0 },
                                           std::vector<uint8_t>{ 3, 0x01, 1, 0x01, 9, 0, 0, 0, 5, 6, 7 } })
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
