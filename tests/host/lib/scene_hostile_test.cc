// Scene files that try to hurt the host library, systematically: every JSON leaf of a valid
// tissue and scene replaced by each wrong type or magnitude, every cut of every kind of file, each
// CSV value and PGM byte damaged — each refused with a reason in words (never the JSON library's
// own message) or accepted and then round-tripping; and inputs of any value rendered from accepted
// tissues never ask a finger past its curve.
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

#include <nlohmann/json.hpp>

#include "palpa/host/scene_file.h"
#include "palpa/host/scene_image.h"
#include "palpa/host/scene_input.h"
#include "palpa/host/scene_render.h"
#include "palpa/host/scene_tablet.h"
#include "palpa/host/scene_tactile.h"
#include "small_tissue.h"

#include "CppUTest/TestHarness.h"
#include "scene_examples.h"

namespace ph = palpa::host;
namespace pp = palpa::protocol;
using nlohmann::json;

namespace {

/// A refusal says what is wrong in words: not empty, not the JSON library's message.
void CheckReason(const ph::Outcome& o, const std::string& text) {
  CHECK_TEXT(!o.message.empty(), ("refused without a reason: " + text.substr(0, 200)).c_str());
  CHECK_TEXT(o.message.find("[json.exception") == std::string::npos, o.message.c_str());
}

const json kWrong[] = {nullptr,        "x",  -1,  0,   1e300, -1e300, 2147483648.0, json::array(),
                       json::object(), true, 0.5, 1025};

/// Every leaf of `valid` replaced by each wrong value, and removed: `check` gets each text.
template <class Check>
void EveryLeaf(const std::string& valid, Check check) {
  const json doc = json::parse(valid);
  const json flat = doc.flatten();
  for (const auto& leaf : flat.items()) {
    const json::json_pointer where(leaf.key());
    for (const json& wrong : kWrong) {
      json j = doc;
      j[where] = wrong;
      check(j.dump());
    }
    json j = doc;
    json& parent = j[where.parent_pointer()];
    if (parent.is_object()) parent.erase(where.back());
    if (parent.is_array()) parent.erase(std::stoul(where.back()));
    check(j.dump());
  }
}

/// Every cut of `text` (each length from 0), and a few byte values written at each place.
template <class Check>
void EveryCutAndByte(const std::string& text, Check check) {
  for (size_t n = 0; n < text.size(); ++n) check(text.substr(0, n));
  for (size_t at = 0; at < text.size(); ++at) {
    for (const char b : {'\0', '\n', ',', '-', 'e', '9', '\xff', ' '}) {
      std::string damaged = text;
      damaged[at] = b;
      check(damaged);
    }
  }
}

/// A tissue that was accepted renders, for inputs of any value, targets inside each finger's curve.
void RendersWithinLimits(const ph::TissueMap& tissue) {
  const ph::RenderFinger pneumatic{
      0, {pp::FingerKind::kPneumatic, pp::FingerMode::kTarget, 0, pp::kNoLine}, {}};
  const ph::RenderFinger jamming{1, {pp::FingerKind::kJamming, pp::FingerMode::kTarget, 1, 2}, {}};
  const auto r =
      ph::SceneRenderer::Make(tissue, ph::JammingPairLayout(3, 2), {}, {pneumatic, jamming});
  CHECK_TEXT(r.ok(), r.message.c_str());
  const double odd[] = {0, 2.5, -1e9, NAN, INFINITY};  // on the map, off it, not a number
  for (double x : odd) {
    for (double y : odd) {
      for (double force : odd) {
        for (const ph::FingerRender& f : r.value.Render({0, x, y, force})) {
          CHECK(f.mapped.status == pp::Status::kOk);
          CHECK(f.mapped.target >= 0 && f.mapped.target <= 4370);
        }
      }
    }
  }
}

}  // namespace

TEST_GROUP(SceneHostileFiles){};

TEST(SceneHostileFiles, TissueFilesAreRefusedWithAReasonOrRoundTrip) {
  const std::string valid = ph::SerializeTissue(palpa::testing::SmallTissue()).value;
  size_t accepted = 0;
  auto check = [&](const std::string& text) {
    const auto m = ph::ParseTissue(text);
    if (!m.ok()) return CheckReason(m, text);
    ++accepted;
    CHECK_TEXT(ph::CheckTissue(m.value).ok(), text.c_str());
    const auto again = ph::SerializeTissue(m.value);
    CHECK_TEXT(again.ok(), again.message.c_str());
    STRCMP_EQUAL(again.value.c_str(),
                 ph::SerializeTissue(ph::ParseTissue(again.value).value).value.c_str());
    RendersWithinLimits(m.value);
  };
  EveryLeaf(valid, check);
  EveryCutAndByte(valid, check);
  CHECK(accepted > 0);  // some changes are still tissues (another value in range)
}

TEST(SceneHostileFiles, SceneFilesAreRefusedWithAReasonOrRoundTrip) {
  const std::string valid =
      ph::ReadFileWhole(palpa::testing::kThreeCubeScene, ph::kSceneFileLimits).value;
  auto check = [&](const std::string& text) {
    const auto s = ph::ParseScene(text);
    if (!s.ok()) return CheckReason(s, text);
    const auto written = ph::SerializeScene(s.value);
    CHECK_TEXT(written.ok(), written.message.c_str());
    STRCMP_EQUAL(written.value.c_str(),
                 ph::SerializeScene(ph::ParseScene(written.value).value).value.c_str());
  };
  EveryLeaf(valid, check);
  EveryCutAndByte(valid, check);
}

TEST(SceneHostileFiles, SceneInputSectionsAreRefusedWithAReasonOrRoundTrip) {
  const std::string valid =
      ph::ReadFileWhole(PALPA_DOCS_DIR "/examples/scene_inputs.json", ph::kSceneFileLimits).value;
  size_t accepted = 0;
  EveryLeaf(valid, [&](const std::string& text) {
    const auto s = ph::ParseScene(text);
    if (!s.ok()) return CheckReason(s, text);
    ++accepted;
    const auto written = ph::SerializeScene(s.value);
    CHECK_TEXT(written.ok(), written.message.c_str());
    if (s.value.tactile)
      CHECK(ph::CheckTactile(*s.value.tactile, s.value.board_fingers.size()).ok());
    if (s.value.tablet) CHECK(ph::CheckPressureForce(s.value.tablet->pressure_force).ok());
  });
  CHECK(accepted > 0);
}

TEST(SceneHostileFiles, TactileStreamsAndPressesAreRefusedWithAReasonOrHoldTheirRules) {
  EveryCutAndByte("time_s,a,b\n0,1,2\n0.01,3,4.5\n", [](const std::string& text) {
    const auto frames = ph::ParseTactileStream(text, "s.csv", 2);
    if (!frames.ok()) return CheckReason(frames, text);
    for (size_t k = 0; k < frames.value.size(); ++k) {
      CHECK(frames.value[k].values.size() == 2);
      if (k > 0) CHECK(frames.value[k].time_s > frames.value[k - 1].time_s);
    }
  });
  EveryCutAndByte("level,force_n\n100,0.2\n900,3\n", [](const std::string& text) {
    const auto presses = ph::ParsePresses(text, "p.csv");
    if (!presses.ok()) return CheckReason(presses, text);
    const auto fit = ph::FitPressureForce(presses.value);
    if (!fit.ok()) return CheckReason(fit, text);
    CHECK(ph::CheckPressureForce(fit.value.model).ok());
  });
  // Datagrams: every cut and byte of a valid frame decodes whole or is refused in words.
  const auto packet = ph::EncodeTactilePacket(3, {1, 2});
  const std::string bytes(packet.begin(), packet.end());
  EveryCutAndByte(bytes, [](const std::string& text) {
    const auto f =
        ph::DecodeTactilePacket(reinterpret_cast<const uint8_t*>(text.data()), text.size(), 2);
    if (!f.ok()) return CheckReason(f, "a datagram");
    CHECK(f.value.values.size() == 2);
  });
}

TEST(SceneHostileFiles, ForceMatricesAndTrajectoriesAreRefusedWithAReasonOrHoldTheirRules) {
  EveryCutAndByte("# depth 2 mm\n1.5, 2, 3e0\n4,5,6\n", [](const std::string& text) {
    const auto rows = ph::ParseForceMatrix(text, "m.csv");
    if (!rows.ok()) return CheckReason(rows, text);
    for (const auto& row : rows.value) {
      CHECK(row.size() == rows.value[0].size());
      for (double v : row) CHECK(std::isfinite(v));
    }
  });
  EveryCutAndByte("time_s,x_mm,y_mm,force_n\n0,1,2,0.5\n0.25,-3,4,1\n",
                  [](const std::string& text) {
                    const auto t = ph::ParseTrajectory(text, "t.csv");
                    if (!t.ok()) return CheckReason(t, text);
                    for (size_t k = 0; k < t.value.size(); ++k) {
                      CHECK(t.value[k].force_n >= 0 && t.value[k].force_n <= ph::kMaxInputForceN);
                      CHECK(std::isfinite(t.value[k].x_mm) && std::isfinite(t.value[k].y_mm));
                      if (k > 0) CHECK(t.value[k].time_s > t.value[k - 1].time_s);
                    }
                  });
}

TEST(SceneHostileFiles, ImagesAreRefusedWithAReasonOrMakeAWholeMap) {
  const ph::ImageScale scale{"img", "kPa", 0.5, 10, 30};
  auto check = [&](const std::string& bytes) {
    const auto m = ph::ParseTissueImage(bytes, scale, "i.pgm");
    if (!m.ok()) return CheckReason(m, bytes);
    CHECK_TEXT(ph::CheckTissue(m.value).ok(), bytes.c_str());
    for (double v : m.value.values) CHECK(v >= 10 && v <= 30);
  };
  EveryCutAndByte("P2\n# c\n3 2\n255\n0 128 255\n255 0 7\n", check);
  EveryCutAndByte(
      std::string("P5 3 2 65535\n") + std::string("\0\0\xff\xff\x80\0\0\x01\x02\x03\xff\0", 12),
      check);
}
