// Tactile arrays: groups checked and averaged, the scene file's input section read and written
// with each bad field named, recorded streams and UDP frames refused part by part, and a recorded
// stream replayed through the renderer — fingers following their groups' means, held through a
// short stall, soft after a long one, late packets never rendered.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cmath>
#include <string>

#include "palpa/host/scene_file.h"
#include "palpa/host/scene_phantom.h"
#include "palpa/host/scene_render.h"
#include "palpa/host/scene_tactile.h"

#include "CppUTest/TestHarness.h"
#include "text_checks.h"

namespace ph = palpa::host;
namespace pp = palpa::protocol;

namespace {

const char kInputsScene[] = PALPA_DOCS_DIR "/examples/scene_inputs.json";
const char kStream[] = PALPA_DOCS_DIR "/examples/tactile_grasper.csv";

ph::TactileSpec Spec() {
  ph::TactileSpec s;
  s.elements = 9;
  s.groups = {{0, 1, 2}, {3, 4, 5}, {6, 7, 8}};
  s.unit = "kPa";
  s.value_lo = 0, s.value_hi = 40;
  return s;
}

std::string SceneRefusal(const std::string& input) {
  const std::string text = R"({"schema": "palpa-scene", "schema_version": 1, "name": "t",
    "tissue": {"preset": "thesis-three-cube"},
    "layout": {"kind": "row", "count": 3, "spacing_mm": 15, "contact_diameter_mm": 4},
    "fingers": [0, 1, 2], "rule": {"contrast": 1, "contact_force_n": 0.05,
    "pneumatic": {"mapping": "deformation"}}, "input": )" +
                           input + "}";
  const auto s = ph::ParseScene(text);
  CHECK_TEXT(!s.ok(), ("accepted: " + input).c_str());
  return s.message;
}

ph::SceneRenderer Renderer() {
  auto tissue = ph::GeneratePhantom(ph::ThreeCubePhantom());
  CHECK(tissue.ok());
  std::vector<ph::RenderFinger> fingers(3);
  for (uint8_t f = 0; f < 3; ++f) fingers[f].board_finger = f;
  ph::RenderRule rule;
  rule.deformation_hi_mm = 2;  // u = 1 is 2 mm
  auto r = ph::SceneRenderer::Make(std::move(tissue.value), ph::RowLayout(3, 15, 4), rule, fingers);
  CHECK_TEXT(r.ok(), r.message.c_str());
  return std::move(r.value);
}

}  // namespace

TEST_GROUP(SceneTactile){};

TEST(SceneTactile, GroupsAveraged) {
  const std::vector<double> values{1, 2, 3, 10, 20, 30, 0, 0, 9};
  const auto means = ph::GroupMeans(Spec(), values);
  LONGS_EQUAL(3, means.size());
  DOUBLES_EQUAL(2, means[0], 1e-12);
  DOUBLES_EQUAL(20, means[1], 1e-12);
  DOUBLES_EQUAL(3, means[2], 1e-12);
  ph::TactileSpec two = Spec();  // the jamming system's two groups, overlapping is allowed
  two.groups = {{0, 1, 2, 3, 4}, {4, 5, 6, 7, 8}};
  CHECK(ph::CheckTactile(two, 2).ok());
  DOUBLES_EQUAL((20 + 30 + 0 + 0 + 9) / 5.0, ph::GroupMeans(two, values)[1], 1e-12);
}

TEST(SceneTactile, BadSpecsNamed) {
  ph::TactileSpec s = Spec();
  CHECK(ph::CheckTactile(s, 3).ok());
  CHECK_CONTAINS(ph::CheckTactile(s, 2).message,
                 "tactile.groups: 3 groups for the layout's 2 fingers");
  s.groups[1][2] = 9;
  CHECK_CONTAINS(ph::CheckTactile(s, 3).message,
                 "tactile.groups[1][2]: element 9 is beyond the array's 9 (0 … 8)");
  s.groups[1] = {3, 3};
  CHECK_CONTAINS(ph::CheckTactile(s, 3).message, "tactile.groups[1][1]: element 3 is in the group");
  s = Spec();
  s.hold_s = 5;
  CHECK_CONTAINS(ph::CheckTactile(s, 3).message, "tactile.hold_s: 5 s is outside 0 … 2 s");
  s = Spec();
  s.value_lo = 40;
  CHECK_CONTAINS(ph::CheckTactile(s, 3).message, "tactile.value_range: must rise");
}

TEST(SceneTactile, SceneFileInputSectionRoundTrips) {
  const auto spec = ph::LoadScene(kInputsScene);
  CHECK_TEXT(spec.ok(), spec.message.c_str());
  CHECK(spec.value.tablet && spec.value.tactile);
  DOUBLES_EQUAL(0.0039, spec.value.tablet->pressure_force.b_per_level, 0);
  LONGS_EQUAL(3, spec.value.tactile->groups.size());
  const auto text = ph::SerializeScene(spec.value);
  CHECK_TEXT(text.ok(), text.message.c_str());
  const auto back = ph::ParseScene(text.value);
  CHECK(back.ok());
  CHECK(back.value.tactile->groups == spec.value.tactile->groups);
  DOUBLES_EQUAL(40, back.value.tactile->value_hi, 0);
  DOUBLES_EQUAL(0.0827, back.value.tablet->pressure_force.a_n, 0);
}

TEST(SceneTactile, SceneFileFieldsNamed) {
  CHECK_CONTAINS(SceneRefusal(R"({"pen": {}})"), "input");
  CHECK_CONTAINS(SceneRefusal(R"({"tablet": {"pressure_force": {"a_n": 0, "b_per_level": 0}}})"),
                 "input.tablet.pressure_force.a_n");
  CHECK_CONTAINS(SceneRefusal(R"({"tablet": {"pressure_force": {"a_n": 1, "b_per_level": 0.01}}})"),
                 "input.tablet.pressure_force: a·e^(b·1023)");
  const std::string good_rest = R"(, "unit": "kPa", "value_range": [0, 40]}})";
  CHECK_CONTAINS(SceneRefusal(R"({"tactile": {"elements": 9, "groups": [[0], [1]])" + good_rest),
                 "input.tactile.groups: 2 groups for the layout's 3 fingers");
  CHECK_CONTAINS(
      SceneRefusal(R"({"tactile": {"elements": 9, "groups": [[0], [1], [-1]])" + good_rest),
      "input.tactile.groups[2][0]: must be an element index");
  CHECK_CONTAINS(
      SceneRefusal(R"({"tactile": {"elements": 9, "groups": [[0], [1], []])" + good_rest),
      "input.tactile.groups[2]: must be a list");
  CHECK_CONTAINS(
      SceneRefusal(R"({"tactile": {"elements": 2, "groups": [[0], [1], [2]])" + good_rest),
      "input.tactile.groups[2][0]: element 2 is beyond");
  CHECK_CONTAINS(
      SceneRefusal(R"({"tactile": {"elements": 0, "groups": [[0], [1], [2]])" + good_rest),
      "input.tactile.elements");
}

TEST(SceneTactile, StreamsReadLineByLine) {
  const auto ok = ph::ParseTactileStream("time_s,a,b\n0,1,2\n0.01,3,4\n", "s.csv", 2);
  CHECK_TEXT(ok.ok(), ok.message.c_str());
  LONGS_EQUAL(2, ok.value.size());
  LONGS_EQUAL(1, ok.value[1].sequence);
  DOUBLES_EQUAL(4, ok.value[1].values[1], 0);
  CHECK_CONTAINS(ph::ParseTactileStream("t,a,b\n0,1,2\n", "s.csv", 2).message,
                 "s.csv: line 1: expected the header time_s");
  CHECK_CONTAINS(ph::ParseTactileStream("time_s,a\n0,1\n", "s.csv", 2).message,
                 "s.csv: line 1: 1 element columns, the scene's array has 2");
  CHECK_CONTAINS(ph::ParseTactileStream("time_s,a,b\n0,1\n", "s.csv", 2).message,
                 "s.csv: line 2: 2 values, expected 3");
  CHECK_CONTAINS(ph::ParseTactileStream("time_s,a,b\n0,1,2\n0,1,2\n", "s.csv", 2).message,
                 "s.csv: line 3: time 0 s is not after");
  CHECK_CONTAINS(ph::ParseTactileStream("time_s,a,b\n0,1,nan\n", "s.csv", 2).message,
                 "s.csv: line 2");
}

TEST(SceneTactile, PacketsDecodedPartByPart) {
  const auto bytes = ph::EncodeTactilePacket(7, {1.5, -2, 40});
  LONGS_EQUAL(12 + 12, bytes.size());
  const auto f = ph::DecodeTactilePacket(bytes.data(), bytes.size(), 3);
  CHECK_TEXT(f.ok(), f.message.c_str());
  LONGS_EQUAL(7, f.value.sequence);
  DOUBLES_EQUAL(-2, f.value.values[1], 0);
  CHECK_CONTAINS(ph::DecodeTactilePacket(bytes.data(), 5, 3).message,
                 "shorter than the 12-byte header");
  CHECK_CONTAINS(ph::DecodeTactilePacket(bytes.data(), bytes.size(), 4).message,
                 "3 elements, the scene's array has 4");
  CHECK_CONTAINS(ph::DecodeTactilePacket(bytes.data(), bytes.size() - 1, 3).message,
                 "23 bytes for 3 elements, which take 24");
  auto bad = bytes;
  bad[0] = 'X';
  CHECK_CONTAINS(ph::DecodeTactilePacket(bad.data(), bad.size(), 3).message, "no PTA1 magic");
  bad = bytes;
  bad[11] = 1;
  CHECK_CONTAINS(ph::DecodeTactilePacket(bad.data(), bad.size(), 3).message, "reserved");
  bad = ph::EncodeTactilePacket(7, {1, NAN, 2});
  CHECK_CONTAINS(ph::DecodeTactilePacket(bad.data(), bad.size(), 3).message,
                 "element 1 is not a number");
}

TEST(SceneTactile, HoldThenSoftLateDropped) {
  ph::TactileHold hold(0.1);
  CHECK(hold.At(0) == nullptr);  // nothing yet: soft
  CHECK(hold.Receive({0, 10, {1}}, 0.0));
  DOUBLES_EQUAL(1, (*hold.At(0.05))[0], 0);
  CHECK(hold.Receive({0, 13, {4}}, 0.06));  // 11 and 12 lost
  LONGS_EQUAL(2, hold.missing());
  CHECK(!hold.Receive({0, 12, {3}}, 0.07));  // arrives after 13: late, never rendered
  CHECK(!hold.Receive({0, 13, {9}}, 0.07));  // a duplicate
  LONGS_EQUAL(2, hold.late());
  DOUBLES_EQUAL(4, (*hold.At(0.16))[0], 0);  // held for 0.1 s after it arrived …
  CHECK(hold.At(0.1601) == nullptr);         // … then soft
  // Sequence numbers wrap.
  ph::TactileHold wrap(0.1);
  CHECK(wrap.Receive({0, 0xFFFFFFFFu, {1}}, 0));
  CHECK(wrap.Receive({0, 0, {2}}, 0.01));
  LONGS_EQUAL(0, wrap.missing());
}

TEST(SceneTactile, RecordedStreamReplayedFingersFollowTheGroups) {
  const auto spec = ph::LoadScene(kInputsScene);
  CHECK(spec.ok());
  const ph::TactileSpec& t = *spec.value.tactile;
  const auto frames = ph::LoadTactileStream(kStream, t.elements);
  CHECK_TEXT(frames.ok(), frames.message.c_str());
  const ph::SceneRenderer r = Renderer();
  ph::TactileHold hold(t.hold_s);
  size_t next = 0, held = 0, soft = 0, followed = 0;
  // Replayed at the stream's own times, rendered every 10 ms as a player does between frames.
  // Half a step after each frame's time, so no comparison sits on a rounding boundary.
  double peak_u = 0, middle_u = 0;
  for (int k = 0; k < 300; ++k) {
    const double now = k * 0.01 + 0.005;
    while (next < frames.value.size() && frames.value[next].time_s <= now) {
      const ph::TactileFrame& frame = frames.value[next++];
      hold.Receive(frame, frame.time_s);
    }
    const std::vector<double>* values = hold.At(now);
    std::vector<double> means;
    if (values != nullptr) means = ph::GroupMeans(t, *values);
    const auto renders =
        r.RenderValues(values != nullptr ? &means : nullptr, t.value_lo, t.value_hi);
    const bool in_long_gap = now > 1.49 + t.hold_s && now < 1.80;
    if (in_long_gap) {
      // The stream stalled longer than the hold: every finger soft (released).
      for (const auto& f : renders) CHECK(!f.touching && f.request.value == 0);
      ++soft;
      continue;
    }
    CHECK_TEXT(values != nullptr, ("no values at " + std::to_string(now)).c_str());
    if (now >= 2.21 && now < 2.24) ++held;
    if (k == 100)
      peak_u = renders[0].u, middle_u = renders[1].u;  // a short stall: the last frame held
    for (size_t f = 0; f < 3; ++f) {
      // u is the group's mean over 0 … 40 kPa; the deformation is u × 2 mm.
      const double u = std::clamp(means[f] / 40, 0.0, 1.0);
      DOUBLES_EQUAL(u, renders[f].u, 1e-9);
      DOUBLES_EQUAL(u * 2, renders[f].request.value, 1e-9);
    }
    ++followed;
  }
  LONGS_EQUAL(21, soft);  // 1.595 … 1.795 s: more than 0.1 s after the 1.49 s frame
  LONGS_EQUAL(3, held);
  LONGS_EQUAL(300 - 21, followed);
  LONGS_EQUAL(0, hold.late());
  // Row 0 at the press's peak (t = 1 s: 36, 40, 44 kPa) renders full; row 1 (20 kPa) half.
  DOUBLES_EQUAL(1.0, peak_u, 1e-3);
  DOUBLES_EQUAL(0.5, middle_u, 1e-9);
}

TEST(SceneTactile, UdpFramesReceivedMalformedCounted) {
  auto udp = ph::TactileUdp::Open("127.0.0.1", 0, 3);
  CHECK_TEXT(udp.ok(), udp.message.c_str());
  CHECK(udp.value->port() != 0);
  const int s = socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(udp.value->port());
  to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  const auto send = [&](const std::vector<uint8_t>& b) {
    CHECK(sendto(s, b.data(), b.size(), 0, reinterpret_cast<sockaddr*>(&to), sizeof(to)) ==
          static_cast<ssize_t>(b.size()));
  };
  send(ph::EncodeTactilePacket(1, {1, 2, 3}));
  send(ph::EncodeTactilePacket(2, {1, 2}));  // wrong size for this array
  send(ph::EncodeTactilePacket(3, {4, 5, 6}));
  const double before = ph::MonotonicSeconds();
  auto a = udp.value->Receive(1000);
  CHECK(a.ok() && a.value.has_value());
  LONGS_EQUAL(1, a.value->sequence);
  CHECK(a.value->time_s >= before - 1 && a.value->time_s <= ph::MonotonicSeconds());
  auto b = udp.value->Receive(1000);
  CHECK(b.ok() && !b.value.has_value());  // the malformed one: skipped, counted, said why
  LONGS_EQUAL(1, udp.value->malformed());
  CHECK_CONTAINS(udp.value->last_problem(), "2 elements, the scene's array has 3");
  auto c = udp.value->Receive(1000);
  CHECK(c.ok() && c.value.has_value());
  DOUBLES_EQUAL(6, c.value->values[2], 0);
  auto none = udp.value->Receive(10);
  CHECK(none.ok() && !none.value.has_value());
  close(s);
  // A port in use is refused naming it.
  auto again = ph::TactileUdp::Open("127.0.0.1", udp.value->port(), 3);
  CHECK(!again.ok());
  CHECK_CONTAINS(again.message,
                 "udp:127.0.0.1:" + std::to_string(udp.value->port()) + ": cannot listen there");
}
