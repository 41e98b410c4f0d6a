// The simulated board in-process on virtual time: the core driving the plant end to end.
#include <cmath>
#include <memory>
#include <utility>

#include "palpa/hal/fake/fakes.h"
#include "palpa/protocol/codec.h"
#include "sim_board.h"

#include "CppUTest/TestHarness.h"

namespace ps = palpa::sim;
namespace pp = palpa::protocol;

namespace {

struct Rig {
  palpa::hal::fake::FakeByteLink link;
  std::unique_ptr<ps::SimBoard> sim;
  uint8_t seq = 0;
  uint32_t generation = 0;

  explicit Rig(int level = 3, const char* config = "thesis-5finger") {
    ps::SimBoardOptions o;
    o.config = config;
    o.plant.level = level;
    auto created = ps::SimBoard::Create(o, link);
    CHECK_TEXT(created.ok(), created.message.c_str());
    sim = std::move(created.value);
    Send(pp::Hello{42, 0});
    sim->Advance(2000);
  }
  /// A message naming a session names this one's (the Hello's nonce, 42).
  template <class M>
  void Send(M m, bool reliable = false) {
    if constexpr (requires { m.session; }) m.session = 42;
    uint8_t frame[pp::kMaxFrameSize];
    const auto n = pp::EncodeMessageFrame(
        m, reliable ? seq++ : 0, reliable ? pp::flags::kReliable : 0, frame, sizeof(frame));
    link.Inject(frame, n.value);
  }
  /// Runs with heartbeats every 20 ms.
  void Run(uint32_t ms) {
    for (uint32_t i = 0; i < ms; ++i) {
      if (i % 20 == 0) Send(pp::Heartbeat{42, ++generation});
      sim->Advance(1000);
      link.tx.clear();
    }
  }
};

}  // namespace

TEST_GROUP(SimBoard){};

TEST(SimBoard, UnknownConfigurationIsRefusedWithTheKnownNames) {
  palpa::hal::fake::FakeByteLink link;
  ps::SimBoardOptions o;
  o.config = "thesis-9finger";
  const auto created = ps::SimBoard::Create(o, link);
  CHECK(!created.ok() && created.value == nullptr);
  LONGS_EQUAL(static_cast<int>(pp::Status::kBadValue), static_cast<int>(created.status));
  CHECK_TEXT(created.message.find("--config thesis-9finger: unknown board configuration") == 0 &&
                 created.message.find("thesis-5finger") != std::string::npos,
             created.message.c_str());
}

TEST(SimBoard, RawSetpointReachesTheChamberWithinTheSensorsAccuracy) {
  Rig rig;
  rig.Send(pp::SetFingerMode{0, pp::FingerMode::kRaw}, true);
  pp::SetLineSetpoints sp{};
  sp.generation = 1;
  sp.entry_count = 1;
  sp.entries[0] = {0, 30000};
  rig.Send(sp);
  rig.Run(6000);
  CHECK_FALSE(rig.sim->board().safe());
  const float chamber = rig.sim->plant().Truth().lines[0].chamber_pa;
  // sensor accuracy (0.25 % FSS of 103 kPa) + half the dead band + noise
  DOUBLES_EQUAL(30000, chamber, 258 + 50 + 100);
}

TEST(SimBoard, TargetDeformsThePneumaticFinger) {
  Rig rig(2);
  pp::SetFingerTargets t{};
  t.generation = 1;
  t.entry_count = 1;
  t.entries[0] = {1, pp::OutputUnit::kDeformationMicrometre, 2000};
  rig.Send(t);
  rig.Run(5000);
  const float mm = rig.sim->plant().Truth().fingers[1].deformation_mm;
  // The static inverse with no compensation lands within the hysteresis band around 2 mm.
  CHECK_TEXT(mm > 1.5f && mm < 2.5f, std::to_string(mm).c_str());
}

TEST(SimBoard, JammingTargetStiffensTheFinger) {
  Rig rig(2);
  pp::SetFingerTargets t{};
  t.generation = 1;
  t.entry_count = 1;
  t.entries[0] = {3, pp::OutputUnit::kStiffnessMilliNewtonPerMm, 1200};
  rig.Send(t);
  rig.Run(8000);
  DOUBLES_EQUAL(1.2, rig.sim->plant().Truth().fingers[3].stiffness_n_per_mm, 0.08);
  CHECK(rig.sim->pump_on());
}

TEST(SimBoard, HostLossVentsEveryChamberWithinTimeoutPlusSettling) {
  Rig rig;
  for (uint8_t f = 0; f < 3; ++f) rig.Send(pp::SetFingerMode{f, pp::FingerMode::kRaw}, true);
  pp::SetLineSetpoints sp{};
  sp.generation = 1;
  sp.entry_count = 3;
  for (uint8_t i = 0; i < 3; ++i) sp.entries[i] = {i, 90000};
  rig.Send(sp);
  rig.Run(3000);
  CHECK(rig.sim->plant().Truth().lines[0].chamber_pa > 80000);
  const uint64_t last = rig.sim->now_us();
  uint64_t safe_at = 0, vented_at = 0;
  while (vented_at == 0 && rig.sim->now_us() < last + 2000000) {
    rig.sim->Advance(1000);
    if (safe_at == 0 && rig.sim->board().safe()) safe_at = rig.sim->now_us();
    bool vented = true;
    for (const auto& l : rig.sim->plant().Truth().lines) vented &= std::fabs(l.chamber_pa) < 5000;
    if (vented) vented_at = rig.sim->now_us();
  }
  CHECK(safe_at != 0 &&
        safe_at - last <= 100000 + 1000 + 20000);  // heartbeat phase: up to 20 ms early
  CHECK(!rig.sim->valves_held());
  CHECK_TEXT(vented_at - last <= 100000 + 250000, std::to_string(vented_at - last).c_str());
}
