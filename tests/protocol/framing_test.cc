// Frame decoder: resynchronisation, counters, oversize, glued and truncated frames, random bytes.
#include <random>
#include <vector>

#include "palpa/protocol/cobs.h"
#include "palpa/protocol/codec.h"
#include "palpa/protocol/crc32.h"
#include "palpa/protocol/framing.h"

#include "CppUTest/TestHarness.h"

namespace pp = palpa::protocol;

namespace {

std::vector<uint8_t> FrameOf(const pp::Heartbeat& hb, uint8_t flags = 0) {
  std::vector<uint8_t> out(pp::kMaxFrameSize);
  const auto n = pp::EncodeMessageFrame(hb, 0, flags, out.data(), out.size());
  CHECK(n.ok());
  out.resize(n.value);
  return out;
}

struct Feed {
  pp::OwningFrameDecoder decoder;
  std::vector<uint32_t> generations;
  int errors = 0;

  void Bytes(const std::vector<uint8_t>& bytes) {
    for (uint8_t b : bytes) {
      const auto event = decoder.Process(b);
      if (event == pp::FrameDecoder::Event::kError) ++errors;
      if (event != pp::FrameDecoder::Event::kFrame) continue;
      pp::Heartbeat hb;
      if (decoder.frame().header.type == static_cast<uint8_t>(pp::MessageType::kHeartbeat) &&
          pp::DecodeBody(decoder.frame().body, decoder.frame().body_size, hb) == pp::Status::kOk) {
        generations.push_back(hb.generation);
      }
    }
  }
};

}  // namespace

TEST_GROUP(FrameDecoder){};

TEST(FrameDecoder, DecodesBackToBackFramesAndCountsThem) {
  Feed f;
  std::vector<uint8_t> stream;
  for (uint32_t g = 1; g <= 5; ++g) {
    const auto frame = FrameOf(pp::Heartbeat{0, g});
    stream.insert(stream.end(), frame.begin(), frame.end());
  }
  f.Bytes(stream);
  CHECK((f.generations == std::vector<uint32_t>{1, 2, 3, 4, 5}));
  UNSIGNED_LONGS_EQUAL(5, f.decoder.counters().frames);
  LONGS_EQUAL(0, f.errors);
}

TEST(FrameDecoder, LeadingGarbageIsDroppedAndTheNextFrameDecodes) {
  Feed f;
  f.Bytes({0x13, 0x37, 0x42});
  const auto frame = FrameOf(pp::Heartbeat{0, 9});
  f.Bytes(frame);  // garbage glued to the front of the frame: both discarded together
  CHECK(f.generations.empty());
  UNSIGNED_LONGS_EQUAL(1, f.decoder.counters().garbage + f.decoder.counters().crc_errors);
  f.Bytes(frame);
  CHECK((f.generations == std::vector<uint32_t>{9}));
}

TEST(FrameDecoder, DelimiterBeforeGarbageResynchronises) {
  Feed f;
  f.Bytes({0x13, 0x37, 0x00});
  f.Bytes(FrameOf(pp::Heartbeat{0, 3}));
  CHECK((f.generations == std::vector<uint32_t>{3}));
}

TEST(FrameDecoder, EmptyFramesArePaddingNotErrors) {
  Feed f;
  f.Bytes(std::vector<uint8_t>(64, 0x00));
  UNSIGNED_LONGS_EQUAL(64, f.decoder.counters().empty);
  LONGS_EQUAL(0, f.errors);
}

TEST(FrameDecoder, OversizeFrameIsCountedOnceAndDecoderRecovers) {
  Feed f;
  f.Bytes(std::vector<uint8_t>(5000, 0x7F));
  f.Bytes({0x00});
  UNSIGNED_LONGS_EQUAL(1, f.decoder.counters().oversize);
  f.Bytes(FrameOf(pp::Heartbeat{0, 4}));
  CHECK((f.generations == std::vector<uint32_t>{4}));
}

TEST(FrameDecoder, CrcErrorIsCounted) {
  Feed f;
  auto frame = FrameOf(pp::Heartbeat{0, 0x01020304});
  frame[1] ^= 0x10;  // a data byte (frame[0] and frame[3] are COBS code bytes)
  f.Bytes(frame);
  UNSIGNED_LONGS_EQUAL(1, f.decoder.counters().crc_errors);
  LONGS_EQUAL((int)pp::Status::kCrcError, (int)f.decoder.last_error());
}

TEST(FrameDecoder, WrongVersionAndReservedFlagsAreRejected) {
  uint8_t packet[8] = {2, 0x20, 0, 0, 1, 0, 0, 0};  // version 2
  uint8_t frame[pp::kMaxFrameSize];
  Feed f;
  auto n = pp::EncodeFrame(packet, sizeof(packet), frame, sizeof(frame));
  CHECK(n.ok());
  f.Bytes(std::vector<uint8_t>(frame, frame + n.value));
  UNSIGNED_LONGS_EQUAL(1, f.decoder.counters().version_errors);
  for (uint8_t bit = 4; bit < 8; ++bit) {
    packet[0] = 1;
    packet[3] = static_cast<uint8_t>(1u << bit);
    n = pp::EncodeFrame(packet, sizeof(packet), frame, sizeof(frame));
    f.Bytes(std::vector<uint8_t>(frame, frame + n.value));
  }
  UNSIGNED_LONGS_EQUAL(4, f.decoder.counters().flag_errors);
  CHECK(f.generations.empty());
}

TEST(FrameDecoder, TooShortForHeaderAndCrcIsGarbage) {
  Feed f;
  f.Bytes({0x03, 0x01, 0x02, 0x00});
  UNSIGNED_LONGS_EQUAL(1, f.decoder.counters().garbage);
}

TEST(FrameDecoder, EveryTruncationIsRejected) {
  const auto frame = FrameOf(pp::Heartbeat{0, 77});
  for (size_t cut = 1; cut < frame.size() - 1; ++cut) {
    Feed f;
    std::vector<uint8_t> part(frame.begin(), frame.begin() + static_cast<long>(cut));
    part.push_back(0x00);
    f.Bytes(part);
    CHECK(f.generations.empty());
  }
}

TEST(FrameDecoder, RandomBytesNeverYieldAFrameThatFailsItsCrc) {
  std::mt19937 rng(2024);
  Feed f;
  std::vector<uint8_t> noise(200000);
  for (uint8_t& b : noise) b = static_cast<uint8_t>(rng() % 8 == 0 ? 0 : rng());
  f.Bytes(noise);
  // A random frame passes a 32-bit CRC with probability 2^-32: none expected here.
  UNSIGNED_LONGS_EQUAL(0, f.decoder.counters().frames);
  f.Bytes({0x00});
  f.Bytes(FrameOf(pp::Heartbeat{0, 5}));
  CHECK((f.generations == std::vector<uint32_t>{5}));
}

TEST_GROUP(FrameEncoder){};

TEST(FrameEncoder, RejectsPacketsOutsideTheSizeLimits) {
  uint8_t packet[pp::kMaxPacketSize + 1] = {1, 0x20, 0, 0};
  uint8_t frame[pp::kMaxFrameSize + 8];
  LONGS_EQUAL((int)pp::Status::kBadLength,
              (int)pp::EncodeFrame(packet, 3, frame, sizeof(frame)).status);
  LONGS_EQUAL((int)pp::Status::kBadLength,
              (int)pp::EncodeFrame(packet, sizeof(packet), frame, sizeof(frame)).status);
  CHECK(pp::EncodeFrame(packet, pp::kMaxPacketSize, frame, sizeof(frame)).ok());
}

TEST(FrameEncoder, ReportsOverflowInsteadOfWritingPastTheBuffer) {
  uint8_t packet[pp::kMaxPacketSize] = {1, 0x20, 0, 0};
  for (size_t i = 4; i < sizeof(packet); ++i) packet[i] = static_cast<uint8_t>(i);
  uint8_t frame[pp::kMaxFrameSize];
  const size_t needed = pp::EncodeFrame(packet, sizeof(packet), frame, sizeof(frame)).value;
  CHECK(needed <= pp::kMaxFrameSize);
  for (size_t cap = 0; cap < needed; ++cap) {
    std::vector<uint8_t> out(cap);
    LONGS_EQUAL((int)pp::Status::kOverflow,
                (int)pp::EncodeFrame(packet, sizeof(packet), out.data(), cap).status);
  }
}

TEST(FrameEncoder, MaximumPacketFitsTheMaximumFrame) {
  uint8_t packet[pp::kMaxPacketSize];
  for (uint8_t& b : packet) b = 0xFF;
  packet[0] = 1;
  packet[3] = 0;
  uint8_t frame[pp::kMaxFrameSize];
  const auto n = pp::EncodeFrame(packet, sizeof(packet), frame, sizeof(frame));
  CHECK(n.ok());
  Feed f;
  pp::OwningFrameDecoder& d = f.decoder;
  pp::FrameDecoder::Event last = pp::FrameDecoder::Event::kNone;
  for (size_t i = 0; i < n.value; ++i) last = d.Process(frame[i]);
  CHECK(last == pp::FrameDecoder::Event::kFrame);
  LONGS_EQUAL(pp::kMaxBodySize, d.frame().body_size);
}

namespace {

// The frame as DESIGN §3 defines it, built from the public CRC and COBS: the reference the
// fast encoder must equal byte for byte.
std::vector<uint8_t> ReferenceFrame(const std::vector<uint8_t>& packet) {
  std::vector<uint8_t> raw = packet;
  const uint32_t crc = pp::Crc32(packet.data(), packet.size());
  for (int i = 0; i < 4; ++i) raw.push_back(static_cast<uint8_t>(crc >> (8 * i)));
  std::vector<uint8_t> out(pp::CobsMaxEncodedSize(raw.size()));
  out.resize(pp::CobsEncode(raw.data(), raw.size(), out.data(), out.size()));
  out.push_back(0);
  return out;
}

std::vector<uint8_t> FastFrame(const std::vector<uint8_t>& packet) {
  std::vector<uint8_t> buffer = packet;
  buffer.resize(packet.size() + pp::kCrcSize);
  std::vector<uint8_t> out(pp::kMaxFrameSize + 16);  // room for the word-wise path
  const auto n = pp::EncodeFrameInPlace(buffer.data(), packet.size(), out.data(), out.size());
  CHECK(n.ok());
  out.resize(n.value);
  return out;
}

}  // namespace

TEST(FrameEncoder, WordwisePathEqualsCrcThenCobsForEverySizeAndZeroDensity) {
  std::mt19937 rng(11);
  for (size_t size = pp::kHeaderSize; size <= pp::kMaxPacketSize; ++size) {
    for (int zero_percent : {0, 5, 30, 50, 90, 100}) {
      std::vector<uint8_t> packet(size);
      for (uint8_t& b : packet) {
        b = static_cast<int>(rng() % 100) < zero_percent ? 0 : static_cast<uint8_t>(rng() | 1u);
      }
      CHECK(FastFrame(packet) == ReferenceFrame(packet));
    }
  }
}

TEST(FrameEncoder, WordwisePathSplitsLongZeroFreeRunsAsCobsDoes) {
  // Runs of 250..260 non-zero bytes starting at every offset within a word, with and without a
  // zero after them, and a CRC that may itself contain zeros: every way a 254-byte block can end.
  for (size_t run = 250; run <= 256 - 3; ++run) {
    for (size_t start = 0; start < 4 && start + run <= pp::kMaxPacketSize; ++start) {
      for (bool zero_after : {false, true}) {
        std::vector<uint8_t> packet(start, 0);
        for (size_t i = 0; i < run; ++i) packet.push_back(static_cast<uint8_t>(1 + i % 255));
        if (zero_after && packet.size() < pp::kMaxPacketSize) packet.push_back(0);
        if (packet.size() < pp::kHeaderSize) continue;
        CHECK(FastFrame(packet) == ReferenceFrame(packet));
      }
    }
  }
}
