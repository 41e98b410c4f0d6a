// Golden frames: encode the recorded fields and compare bytes; decode the bytes and compare
// fields; flip every bit and require rejection. The JSON file is the frozen wire contract.
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include "palpa/host/json_fields.h"
#include "palpa/protocol/codec.h"

#include "CppUTest/TestHarness.h"

namespace pp = palpa::protocol;
using palpa::host::json;

namespace {

json LoadGolden() {
  std::ifstream in(PALPA_GOLDEN_FRAMES);
  CHECK_TEXT(in.good(), "cannot open " PALPA_GOLDEN_FRAMES);
  return json::parse(in);
}

struct Decoded {
  bool frame = false;
  pp::Header header;
  std::vector<uint8_t> body;
};

Decoded DecodeWire(const std::vector<uint8_t>& wire) {
  pp::OwningFrameDecoder decoder;
  Decoded out;
  for (uint8_t b : wire) {
    if (decoder.Process(b) == pp::FrameDecoder::Event::kFrame) {
      out.frame = true;
      out.header = decoder.frame().header;
      out.body.assign(decoder.frame().body, decoder.frame().body + decoder.frame().body_size);
    }
  }
  return out;
}

}  // namespace

TEST_GROUP(GoldenFrames) {
  json golden;
  void setup() override { golden = LoadGolden(); }
};

TEST(GoldenFrames, EncodingTheFieldsGivesTheRecordedBytes) {
  for (const json& g : golden) {
    const std::string name = g.at("name");
    const bool known = palpa::host::WithMessageNamed(g.at("type"), [&]<class M>() {
      const M m = palpa::host::MessageFromJson<M>(g.at("fields"));
      uint8_t frame[pp::kMaxFrameSize];
      pp::FieldError e;
      const auto n =
          pp::EncodeMessageFrame(m, g.at("seq"), g.at("flags"), frame, sizeof(frame), &e);
      CHECK_TEXT(n.ok(), (name + ": " + pp::StatusName(n.status)).c_str());
      STRCMP_EQUAL_TEXT(g.at("hex").get<std::string>().c_str(),
                        palpa::host::ToHex(frame, n.value).c_str(), name.c_str());
    });
    CHECK_TEXT(known, name.c_str());
  }
}

TEST(GoldenFrames, DecodingTheBytesGivesTheRecordedFields) {
  for (const json& g : golden) {
    const std::string name = g.at("name");
    const Decoded d = DecodeWire(palpa::host::FromHex(g.at("hex")));
    CHECK_TEXT(d.frame, name.c_str());
    LONGS_EQUAL_TEXT(g.at("seq").get<int>(), d.header.seq, name.c_str());
    LONGS_EQUAL_TEXT(g.at("flags").get<int>(), d.header.flags, name.c_str());
    const pp::MessageInfo* info = pp::FindMessageInfo(d.header.type);
    CHECK_TEXT(info != nullptr, name.c_str());
    STRCMP_EQUAL_TEXT(g.at("type").get<std::string>().c_str(), info->name, name.c_str());
    palpa::host::WithMessageNamed(info->name, [&]<class M>() {
      M m{};
      pp::FieldError e;
      const auto status = pp::DecodeBody(d.body.data(), d.body.size(), m, &e);
      CHECK_TEXT(status == pp::Status::kOk, (name + ": " + (e.field ? e.field : "?")).c_str());
      // Compare through the codec's own view so float text formatting does not matter.
      const json expected =
          palpa::host::MessageToJson(palpa::host::MessageFromJson<M>(g.at("fields")));
      STRCMP_EQUAL_TEXT(expected.dump().c_str(), palpa::host::MessageToJson(m).dump().c_str(),
                        name.c_str());
    });
  }
}

TEST(GoldenFrames, EverySingleBitFlipIsRejectedOrDecodesTheSameFrame) {
  for (const json& g : golden) {
    const std::vector<uint8_t> wire = palpa::host::FromHex(g.at("hex"));
    const Decoded original = DecodeWire(wire);
    for (size_t byte = 0; byte < wire.size(); ++byte) {
      for (int bit = 0; bit < 8; ++bit) {
        std::vector<uint8_t> flipped = wire;
        flipped[byte] ^= static_cast<uint8_t>(1u << bit);
        const Decoded d = DecodeWire(flipped);
        if (d.frame) {
          CHECK_TEXT(d.body == original.body && d.header.type == original.header.type,
                     g.at("name").get<std::string>().c_str());
        }
      }
    }
  }
}

TEST(GoldenFrames, CoverEveryMessageTypeAndTheEdgeCases) {
  std::set<std::string> types;
  size_t largest_packet = 0;
  bool zero_body = false, ff_body = false;
  for (const json& g : golden) {
    types.insert(g.at("type").get<std::string>());
    const Decoded d = DecodeWire(palpa::host::FromHex(g.at("hex")));
    largest_packet = std::max(largest_packet, d.body.size() + pp::kHeaderSize);
    size_t zeros = 0, ffs = 0;
    for (uint8_t b : d.body) {
      zeros += b == 0x00;
      ffs += b == 0xFF;
    }
    zero_body |= d.body.size() > 200 && zeros * 10 >= d.body.size() * 9;
    ff_body |= d.body.size() > 200 && ffs * 10 >= d.body.size() * 9;
  }
  pp::ForEachMessage(pp::Catalog{}, [&]<class M>() {
    CHECK_TEXT(types.count(M::kInfo.name) == 1, M::kInfo.name);
  });
  LONGS_EQUAL(pp::kMaxPacketSize, largest_packet);
  CHECK(zero_body);
  CHECK(ff_body);
}
