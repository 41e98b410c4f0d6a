// CRC-32 against zlib's known values, and COBS against the reference vectors and at random.
#include <algorithm>
#include <random>
#include <vector>

#include "palpa/protocol/cobs.h"
#include "palpa/protocol/crc32.h"
#include "palpa/protocol/wire.h"

#include "CppUTest/TestHarness.h"

namespace pp = palpa::protocol;

TEST_GROUP(Crc32){};

TEST(Crc32, MatchesZlibCheckValue) {
  const uint8_t check[] = {'1', '2', '3', '4', '5', '6', '7', '8', '9'};
  UNSIGNED_LONGS_EQUAL(0xCBF43926u, pp::Crc32(check, sizeof(check)));
}

TEST(Crc32, EmptyInputIsZero) { UNSIGNED_LONGS_EQUAL(0u, pp::Crc32(nullptr, 0)); }

TEST(Crc32, IncrementalEqualsWholeForEverySplit) {
  std::vector<uint8_t> data(257);
  for (size_t i = 0; i < data.size(); ++i) data[i] = static_cast<uint8_t>(i * 37 + 11);
  const uint32_t whole = pp::Crc32(data.data(), data.size());
  for (size_t split = 0; split <= data.size(); ++split) {
    const uint32_t first = pp::Crc32Update(0, data.data(), split);
    UNSIGNED_LONGS_EQUAL(whole, pp::Crc32Update(first, data.data() + split, data.size() - split));
  }
}

TEST(Crc32, ZlibValueOfAllZeroAndAllOnesBlocks) {
  // zlib.crc32(bytes(32)) and zlib.crc32(b'\xff' * 32)
  std::vector<uint8_t> zeros(32, 0x00), ones(32, 0xFF);
  UNSIGNED_LONGS_EQUAL(0x190A55ADu, pp::Crc32(zeros.data(), zeros.size()));
  UNSIGNED_LONGS_EQUAL(0xFF6CAB0Bu, pp::Crc32(ones.data(), ones.size()));
}

TEST_GROUP(Cobs){};

namespace {

std::vector<uint8_t> Encode(const std::vector<uint8_t>& in) {
  std::vector<uint8_t> out(pp::CobsMaxEncodedSize(in.size()));
  const size_t n = pp::CobsEncode(in.data(), in.size(), out.data(), out.size());
  out.resize(n);
  return out;
}

bool Decode(const std::vector<uint8_t>& in, std::vector<uint8_t>& out) {
  pp::CobsDecoder decoder;
  out.clear();
  for (uint8_t b : in) {
    if (b == 0) return false;
    uint8_t decoded[2];
    const size_t n = decoder.Feed(b, decoded);
    out.insert(out.end(), decoded, decoded + n);
  }
  return decoder.Complete();
}

void CheckVector(const std::vector<uint8_t>& raw, const std::vector<uint8_t>& encoded) {
  const std::vector<uint8_t> got = Encode(raw);
  CHECK(got == encoded);
  std::vector<uint8_t> back;
  CHECK(Decode(encoded, back));
  CHECK(back == raw);
}

}  // namespace

TEST(Cobs, ReferenceVectors) {
  CheckVector({}, {0x01});
  CheckVector({0x00}, {0x01, 0x01});
  CheckVector({0x00, 0x00}, {0x01, 0x01, 0x01});
  CheckVector({0x11, 0x22, 0x00, 0x33}, {0x03, 0x11, 0x22, 0x02, 0x33});
  CheckVector({0x11, 0x22, 0x33, 0x44}, {0x05, 0x11, 0x22, 0x33, 0x44});
  CheckVector({0x11, 0x00, 0x00, 0x00}, {0x02, 0x11, 0x01, 0x01, 0x01});
}

TEST(Cobs, LongRunsSplitAt254) {
  std::vector<uint8_t> raw(254);
  for (size_t i = 0; i < raw.size(); ++i) raw[i] = static_cast<uint8_t>(i + 1 > 255 ? 1 : i + 1);
  std::vector<uint8_t> expected(raw.size() + 1, 0xFF);
  std::copy(raw.begin(), raw.end(), expected.begin() + 1);
  CheckVector(raw, expected);  // exactly one full block: no trailing code byte

  raw.push_back(0xAB);  // 255 bytes: a full block, then a block of one
  expected.push_back(0x02);
  expected.push_back(0xAB);
  CheckVector(raw, expected);

  std::vector<uint8_t> zero_after(254, 0x42);
  zero_after.push_back(0x00);
  std::vector<uint8_t> enc(255, 0x42);
  enc[0] = 0xFF;
  enc.push_back(0x01);
  enc.push_back(0x01);
  CheckVector(zero_after, enc);
}

TEST(Cobs, RandomRoundTripsAndNeverEmitsZero) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 2000; ++trial) {
    std::vector<uint8_t> raw(rng() % 700);
    const int zero_percent = static_cast<int>(rng() % 101);
    for (uint8_t& b : raw)
      b = (static_cast<int>(rng() % 100) < zero_percent) ? 0 : static_cast<uint8_t>(rng());
    const std::vector<uint8_t> enc = Encode(raw);
    CHECK(enc.size() <= pp::CobsMaxEncodedSize(raw.size()));
    for (uint8_t b : enc) CHECK(b != 0);
    std::vector<uint8_t> back;
    CHECK(Decode(enc, back));
    CHECK(back == raw);
  }
}

TEST(Cobs, EncoderReportsOverflowForEveryShortBuffer) {
  const std::vector<uint8_t> raw(300, 0x5A);
  const size_t needed = Encode(raw).size();
  std::vector<uint8_t> out(needed);
  for (size_t cap = 0; cap < needed; ++cap) {
    LONGS_EQUAL(0, pp::CobsEncode(raw.data(), raw.size(), out.data(), cap));
  }
  LONGS_EQUAL(needed, pp::CobsEncode(raw.data(), raw.size(), out.data(), needed));
}

TEST(Cobs, TruncatedEncodingIsIncomplete) {
  std::vector<uint8_t> back;
  CHECK_FALSE(Decode({0x05, 0x11, 0x22}, back));
  CHECK_FALSE(Decode({}, back));
}
