// host_files_fuzz's scene kinds: scene files (with and without input sections), tissues as a JSON
// grid, a CSV force matrix or a PGM image, trajectory CSVs, tactile streams and datagrams, and pen
// presses. Each is refused with a reason in words, or accepted and then holds
// its rules: a scene file and a JSON tissue round-trip, an accepted tissue passes the map's checks
// and renders, for inputs of any value (NaN and infinities included), targets the fingers' curves
// allow; a force matrix's rows are one length of finite numbers; an image's values lie within its
// scale; a trajectory's times rise and its forces and positions are finite and in range.
#include <cmath>
#include <string>

#include "fuzz_host_files.h"
#include "palpa/host/file_read.h"
#include "palpa/host/scene_file.h"
#include "palpa/host/scene_image.h"
#include "palpa/host/scene_input.h"
#include "palpa/host/scene_render.h"
#include "palpa/host/scene_tablet.h"
#include "palpa/host/scene_tactile.h"
#include "small_tissue.h"

namespace ph = palpa::host;
namespace pp = palpa::protocol;

namespace palpa::testing::files_fuzz {
namespace {

const std::string& ValidSceneText() {
  static const std::string text =
      ph::ReadFileWhole(PALPA_DOCS_DIR "/examples/scene_three_cube.json", ph::kSceneFileLimits)
          .value;
  return text;
}

/// A scene with both input sections (a pen tablet's pressure form, a tactile array's groups).
const std::string& ValidInputsSceneText() {
  static const std::string text =
      ph::ReadFileWhole(PALPA_DOCS_DIR "/examples/scene_inputs.json", ph::kSceneFileLimits).value;
  return text;
}

/// A small tissue with two depth layers, as written now.
const std::string& ValidTissueText() {
  static const std::string text = [] {
    const auto s = ph::SerializeTissue(SmallTissue());
    if (!s.ok()) Fail("the reference tissue does not serialise", s.message);
    return s.value;
  }();
  return text;
}

/// An accepted tissue: the map's checks, and every input the fuzzer picks rendered by a
/// pneumatic and a jamming finger (nominal curves) to a target their curves allow.
void CheckAcceptedTissue(Bytes& in, const ph::TissueMap& tissue, const std::string& text) {
  if (const ph::Outcome o = ph::CheckTissue(tissue); !o.ok())
    Fail("an accepted tissue fails the map's checks", o.message + " in " + text.substr(0, 200));
  const ph::RenderFinger pneumatic{
      0, {pp::FingerKind::kPneumatic, pp::FingerMode::kTarget, 0, pp::kNoLine}, {}};
  const ph::RenderFinger jamming{1, {pp::FingerKind::kJamming, pp::FingerMode::kTarget, 1, 2}, {}};
  const auto scene =
      ph::SceneRenderer::Make(tissue, ph::JammingPairLayout(3, 2), {}, {pneumatic, jamming});
  if (!scene.ok()) Fail("an accepted tissue makes no scene", scene.message);
  for (int k = 0; k < 4; ++k) {
    const double x = in.FloatBits(), y = in.FloatBits(), force = in.FloatBits();
    for (const ph::FingerRender& f : scene.value.Render({0, x, y, force})) {
      if (f.mapped.status != pp::Status::kOk || f.mapped.target < 0)
        Fail("an accepted tissue renders a target the finger cannot take", f.mapped.error);
    }
  }
}

void CheckScene(const std::string& text) {
  const auto s = ph::ParseScene(text);
  if (!s.ok()) return CheckReason("scene file", s.message, text);
  const auto written = ph::SerializeScene(s.value);
  if (!written.ok()) Fail("an accepted scene file does not serialise", written.message);
  const auto again = ph::ParseScene(written.value);
  if (!again.ok()) Fail("a serialised scene file does not parse back", again.message);
  const auto rewritten = ph::SerializeScene(again.value);
  if (!rewritten.ok() || rewritten.value != written.value)
    Fail("a scene file changes in a round trip", written.value);
}

void CheckTissueText(Bytes& in, const std::string& text) {
  const auto m = ph::ParseTissue(text);
  if (!m.ok()) return CheckReason("tissue", m.message, text);
  const auto written = ph::SerializeTissue(m.value);
  if (!written.ok()) Fail("an accepted tissue does not serialise", written.message);
  const auto again = ph::ParseTissue(written.value);
  if (!again.ok()) Fail("a serialised tissue does not parse back", again.message);
  const auto rewritten = ph::SerializeTissue(again.value);
  if (!rewritten.ok() || rewritten.value != written.value)
    Fail("a tissue changes in a round trip", written.value.substr(0, 200));
  CheckAcceptedTissue(in, m.value, text);
}

void CheckForceMatrix(const std::string& text) {
  const auto rows = ph::ParseForceMatrix(text, "m.csv");
  if (!rows.ok()) return CheckReason("force matrix", rows.message, text);
  for (const auto& row : rows.value) {
    if (row.size() != rows.value[0].size()) Fail("an accepted force matrix is ragged", text);
    for (double v : row) {
      if (!std::isfinite(v)) Fail("an accepted force matrix holds a non-finite value", text);
    }
  }
}

void CheckImage(Bytes& in, const std::string& bytes) {
  const ph::ImageScale scale{"img", "kPa", 0.5, 10, 30};
  const auto m = ph::ParseTissueImage(bytes, scale, "i.pgm");
  if (!m.ok()) return CheckReason("image", m.message, bytes);
  for (double v : m.value.values) {
    if (!(v >= 10 && v <= 30)) Fail("an accepted image has a value outside its scale", bytes);
  }
  CheckAcceptedTissue(in, m.value, bytes);
}

void CheckTrajectory(const std::string& text) {
  const auto t = ph::ParseTrajectory(text, "t.csv");
  if (!t.ok()) return CheckReason("trajectory", t.message, text);
  for (size_t k = 0; k < t.value.size(); ++k) {
    const ph::SceneInput& s = t.value[k];
    if (!(s.force_n >= 0 && s.force_n <= ph::kMaxInputForceN) || !std::isfinite(s.x_mm) ||
        !std::isfinite(s.y_mm) || (k > 0 && !(s.time_s > t.value[k - 1].time_s)))
      Fail("an accepted trajectory breaks its rules", text);
  }
}

/// A tactile stream of two elements: frames of two finite values, time rising.
void CheckTactileStream(const std::string& text) {
  const auto frames = ph::ParseTactileStream(text, "s.csv", 2);
  if (!frames.ok()) return CheckReason("tactile stream", frames.message, text);
  for (size_t k = 0; k < frames.value.size(); ++k) {
    const ph::TactileFrame& f = frames.value[k];
    if (f.values.size() != 2 || !std::isfinite(f.values[0]) || !std::isfinite(f.values[1]) ||
        (k > 0 && !(f.time_s > frames.value[k - 1].time_s)))
      Fail("an accepted tactile stream breaks its rules", text);
  }
}

/// A tactile datagram for a two-element array: two finite values, or a reason.
void CheckTactilePacket(const std::string& bytes) {
  const auto f =
      ph::DecodeTactilePacket(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size(), 2);
  if (!f.ok()) return CheckReason("tactile datagram", f.message, bytes);
  if (f.value.values.size() != 2 || !std::isfinite(f.value.values[0]) ||
      !std::isfinite(f.value.values[1]))
    Fail("an accepted tactile datagram breaks its rules", bytes);
}

/// Presses: refused in words, or fitted to a form within the input's force limit, or refused.
void CheckPresses(const std::string& text) {
  const auto presses = ph::ParsePresses(text, "p.csv");
  if (!presses.ok()) return CheckReason("presses", presses.message, text);
  const auto fit = ph::FitPressureForce(presses.value);
  if (!fit.ok()) return CheckReason("presses", fit.message, text);
  if (!ph::CheckPressureForce(fit.value.model).ok() || !std::isfinite(fit.value.rms_n))
    Fail("a pressure form fitted from presses breaks its rules", text);
}

/// A CSV or image's reference: the fuzzer's own bytes, or the reference damaged.
std::string ChangedBytes(Bytes& in, int variant, const std::string& valid) {
  return variant == 0 ? in.Rest() : Damaged(in, valid);
}

}  // namespace

void CheckSceneKind(Bytes& in, int variant) {
  switch (in.Byte() % 10) {
    case 0:
      return CheckScene(ChangedJson(in, variant, ValidSceneText()));
    case 6:
      return CheckScene(ChangedJson(in, variant, ValidInputsSceneText()));
    case 7:
      return CheckTactileStream(ChangedBytes(in, variant, "time_s,a,b\n0,1,2\n0.01,3,4.5\n"));
    case 8: {
      const auto packet = ph::EncodeTactilePacket(3, {1, 2});
      return CheckTactilePacket(
          ChangedBytes(in, variant, std::string(packet.begin(), packet.end())));
    }
    case 9:
      return CheckPresses(ChangedBytes(in, variant, "level,force_n\n100,0.2\n900,3\n"));
    case 1: {
      const std::string text = ChangedJson(in, variant, ValidTissueText());
      return CheckTissueText(in, text);
    }
    case 2:
      return CheckForceMatrix(ChangedBytes(in, variant, "# depth 2 mm\n1.5, 2, 3e0\n4,5,6\n"));
    case 3: {
      const std::string bytes =
          ChangedBytes(in, variant, "P2\n# c\n3 2\n255\n0 128 255\n255 0 7\n");
      return CheckImage(in, bytes);
    }
    case 4: {
      const std::string bytes =
          ChangedBytes(in, variant,
                       std::string("P5 3 2 65535\n") +
                           std::string("\0\0\xff\xff\x80\0\0\x01\x02\x03\xff\0", 12));
      return CheckImage(in, bytes);
    }
    default:
      return CheckTrajectory(
          ChangedBytes(in, variant, "time_s,x_mm,y_mm,force_n\n0,1,2,0.5\n0.25,-3,4,1\n"));
  }
}

}  // namespace palpa::testing::files_fuzz
