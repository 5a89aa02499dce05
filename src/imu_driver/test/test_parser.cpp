#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "imu_driver/core/crista_parser.h"
#include "imu_driver/testing/packet_gen.h"

namespace imu_driver {
namespace {

struct Collector {
  std::vector<HighSpeedRaw> hs;
  std::vector<uint8_t> types;
  CristaParser parser{[this](const FrameView& f) {
    types.push_back(f.type);
    if (f.type == 0xFF) hs.push_back(DecodeHighSpeedPayload(f.payload));
  }};
  void Feed(const std::vector<uint8_t>& b) { parser.Feed(b.data(), b.size()); }
};

void ExpectCounts(const ParserCounts& got, const ParserCounts& want) {
  EXPECT_EQ(got.bytes_in, want.bytes_in);
  EXPECT_EQ(got.bytes_accepted, want.bytes_accepted);
  EXPECT_EQ(got.garbage_bytes, want.garbage_bytes);
  EXPECT_EQ(got.frames_ok, want.frames_ok);
  EXPECT_EQ(got.bad_crc, want.bad_crc);
  EXPECT_EQ(got.bad_length, want.bad_length);
  EXPECT_EQ(got.unknown_type, want.unknown_type);
  EXPECT_EQ(got.truncated, want.truncated);
}

TEST(Parser, OneFrameWholeAndByteByByte) {
  std::mt19937 rng(1);
  std::vector<uint8_t> f;
  const HighSpeedRaw raw = test::RandomFrame(rng, 5, false, &f);
  Collector whole;
  whole.Feed(f);
  ASSERT_EQ(whole.hs.size(), 1u);
  EXPECT_TRUE(test::SameRaw(whole.hs[0], raw));
  Collector bytewise;
  for (uint8_t b : f) {
    EXPECT_TRUE(bytewise.hs.empty());
    bytewise.parser.Feed(&b, 1);
  }
  ASSERT_EQ(bytewise.hs.size(), 1u);
  EXPECT_TRUE(test::SameRaw(bytewise.hs[0], raw));
  EXPECT_EQ(bytewise.parser.pending_bytes(), 0u);
}

TEST(Parser, ValidFrameRightAfterGarbageAndFalseSync) {
  std::mt19937 rng(2);
  std::vector<uint8_t> f;
  const HighSpeedRaw raw = test::RandomFrame(rng, 9, true, &f);
  // Garbage ending in a false sync with a plausible header: the parser must wait,
  // reject it, and then find the real frame that starts inside its window.
  std::vector<uint8_t> s = {0x01, 0x55, 0x55, 0xAA, 0xFF, 18, 0x00};
  s.insert(s.end(), f.begin(), f.end());
  Collector c;
  c.Feed(s);
  ASSERT_EQ(c.hs.size(), 1u);
  EXPECT_TRUE(test::SameRaw(c.hs[0], raw));
  EXPECT_EQ(c.parser.counts().truncated, 1u);  // the false frame's window holds the real sync
  EXPECT_EQ(c.parser.counts().garbage_bytes, 7u);
}

TEST(Parser, EachRejectKind) {
  std::mt19937 rng(3);
  std::vector<uint8_t> f;
  test::RandomFrame(rng, 1, true, &f);
  {
    Collector c;
    auto g = f;
    g[10] ^= 0x01;
    if (g[10] == 0x55 || g[10] == 0xAA) g[10] ^= 0x03;
    c.Feed(g);
    EXPECT_EQ(c.parser.counts().bad_crc, 1u);
    EXPECT_TRUE(c.hs.empty());
  }
  {
    Collector c;
    auto g = f;
    g[3] = 40;  // above the 18-byte maximum
    c.Feed(g);
    EXPECT_EQ(c.parser.counts().bad_length, 1u);
  }
  {
    Collector c;
    const uint8_t p[8] = {};
    c.Feed(EncodeFrame(0xFF, p, 8));  // CRC-valid but not 0xFF's length
    EXPECT_EQ(c.parser.counts().bad_length, 1u);
    EXPECT_TRUE(c.types.empty());
  }
  {
    Collector c;
    const uint8_t p[3] = {1, 2, 3};
    c.Feed(EncodeFrame(0x42, p, 3));
    EXPECT_EQ(c.parser.counts().unknown_type, 1u);
    EXPECT_EQ(c.parser.counts().bytes_accepted, 9u);
    EXPECT_TRUE(c.types.empty());
  }
  {
    Collector c;
    c.Feed(std::vector<uint8_t>(f.begin(), f.begin() + 15));
    EXPECT_EQ(c.parser.counts().truncated, 0u);  // might still complete
    c.parser.Flush();                            // the port closed: it cannot
    EXPECT_EQ(c.parser.counts().truncated, 1u);
    EXPECT_EQ(c.parser.counts().garbage_bytes, 15u);
    EXPECT_EQ(c.parser.pending_bytes(), 0u);
  }
}

TEST(Parser, OtherDefinedTypesAreDeliveredNotCounted) {
  Collector c;
  const uint8_t timing[8] = {0, 0, 0x27, 0x10, 3, 77, 0, 5};
  c.Feed(EncodeFrame(0x03, timing, 8));
  const uint8_t stdev[6] = {1, 2, 3, 4, 5, 6};  // defined type, length not published
  c.Feed(EncodeFrame(0x1F, stdev, 6));
  EXPECT_EQ(c.types, (std::vector<uint8_t>{0x03, 0x1F}));
  EXPECT_EQ(c.parser.counts().unknown_type, 0u);
}

// Every kind of corruption, scripted so that the exact count of each is known;
// fed in random chunk sizes.
TEST(ParserFuzz, ScriptedCorruptionExactCounts) {
  for (unsigned seed = 10; seed < 15; ++seed) {
    std::mt19937 rng(seed);
    const test::ScriptedStream s = test::MakeScriptedStream(rng, 3000);
    Collector c;
    for (size_t i = 0; i < s.bytes.size();) {
      const size_t n = std::min<size_t>(1 + rng() % 64, s.bytes.size() - i);
      c.parser.Feed(&s.bytes[i], n);
      i += n;
    }
    ASSERT_EQ(c.hs.size(), s.valid.size()) << "seed " << seed;
    for (size_t i = 0; i < s.valid.size(); ++i) ASSERT_TRUE(test::SameRaw(c.hs[i], s.valid[i])) << i;
    ExpectCounts(c.parser.counts(), s.expected);
    EXPECT_GT(s.expected.bad_crc, 50u);  // the script exercises every kind
    EXPECT_GT(s.expected.bad_length, 30u);
    EXPECT_GT(s.expected.unknown_type, 30u);
    EXPECT_GT(s.expected.truncated, 50u);
  }
}

// Unconstrained random bytes (sync bytes over-represented) between and inside
// frames: every untouched frame comes out exactly once, in order, and every
// byte is accounted for.
TEST(ParserFuzz, RandomGarbageNothingValidLost) {
  std::mt19937 rng(99);
  const test::RandomStream r = test::MakeRandomStream(rng, 20000);
  const std::vector<uint8_t>& stream = r.bytes;
  const std::vector<HighSpeedRaw>& valid = r.valid;
  Collector c;
  for (size_t i = 0; i < stream.size();) {
    const size_t n = std::min<size_t>(1 + rng() % 200, stream.size() - i);
    c.parser.Feed(&stream[i], n);
    i += n;
  }
  c.parser.Flush();
  ASSERT_EQ(c.hs.size(), valid.size());
  for (size_t i = 0; i < valid.size(); ++i) ASSERT_TRUE(test::SameRaw(c.hs[i], valid[i])) << i;
  const ParserCounts& k = c.parser.counts();
  EXPECT_EQ(k.bytes_in, stream.size());
  EXPECT_EQ(k.bytes_accepted + k.garbage_bytes, k.bytes_in);
  EXPECT_GT(k.bad_crc + k.bad_length + k.truncated, 1000u);
}

}  // namespace
}  // namespace imu_driver
