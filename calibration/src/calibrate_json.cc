// One finger calibrated from JSON options: checked whole before anything starts, then the
// session's phases in palpa calibrate's order.
#include "palpa/calibration/calibrate_json.h"

#include <algorithm>

#include "palpa/calibration/board_rig.h"
#include "palpa/host/json_check.h"

namespace palpa::calibration {
namespace {

using protocol::Status;

struct Request {
  SessionOptions session;
  bool apply = false;
  std::string sim_config = "thesis-5finger";
  double sim_speed = 4;
};

/// The options into a request; throws JsonInvalid naming the field.
Request Parse(const nlohmann::json& j, bool simulated) {
  const host::JsonObject o(
      j, "options",
      {"finger", "out", "quick", "protocol", "compensator", "operators", "target_pct", "max_cycles",
       "allow_fallback", "resume", "previous", "apply", "sim"});
  Request r;
  SessionOptions& s = r.session;
  s.finger = static_cast<uint8_t>(o.Integer("finger", 0, protocol::kMaxFingers - 1));
  s.out_dir = o.Text("out");
  if (s.out_dir.empty()) throw host::JsonInvalid("options.out: a directory is needed");
  const bool quick = o.Has("quick") && o.Flag("quick");
  ProtocolOptions& p = s.protocol;
  p = quick ? QuickProtocol() : ProtocolOptions{};
  if (o.Has("protocol") && o.Choice("protocol", {"thesis", "adaptive"}) == "adaptive")
    p.map_protocol = MapProtocol::kAdaptive;
  if (o.Has("compensator")) {
    const std::string kind = o.Choice("compensator", {"auto", "pi", "api"});
    if (kind == "pi") p.compensator = protocol::CompensatorKind::kPrandtlIshlinskii;
    if (kind == "api") p.compensator = protocol::CompensatorKind::kAsymmetricPi;
  }
  if (o.Has("operators")) {
    const long n = o.Integer("operators", 0, 32);
    if (n > 0) p.compensator_operators = static_cast<int>(n);
  }
  if (o.Has("target_pct")) p.adaptive.target_error = o.Number("target_pct", 0.5, 50) / 100;
  if (o.Has("max_cycles"))
    p.adaptive.max_cycles = static_cast<int>(o.Integer("max_cycles", 6, 200));
  p.adaptive.min_cycles = std::min(p.adaptive.min_cycles, p.adaptive.max_cycles);
  s.allow_fallback = o.Has("allow_fallback") && o.Flag("allow_fallback");
  s.resume = o.Has("resume") && o.Flag("resume");
  if (o.Has("previous")) s.previous = o.Text("previous");
  r.apply = o.Has("apply") && o.Flag("apply");
  if (o.Has("sim")) {
    if (!simulated) throw host::JsonInvalid("options.sim: goes with the rig \"sim\"");
    const host::JsonObject sim(o.At("sim"), "options.sim",
                               {"config", "speed", "unit", "seed", "plant", "effects"});
    host::SimulatedPlant plant;
    if (sim.Has("config")) r.sim_config = sim.Text("config");
    if (sim.Has("speed")) r.sim_speed = sim.Number("speed", 1, 10);
    if (sim.Has("unit")) plant.actuator_unit = static_cast<uint32_t>(sim.Integer("unit", 0, 1000));
    if (sim.Has("seed")) plant.seed = static_cast<uint32_t>(sim.Integer("seed", 0, 4294967295L));
    if (sim.Has("plant")) plant.plant_level = static_cast<int>(sim.Integer("plant", 0, 3));
    if (sim.Has("effects")) plant.effects = sim.Text("effects");
    if (const std::string why = host::SimEffectsError(plant.effects); !why.empty())
      throw host::JsonInvalid("options.sim.effects: " + why);
    s.simulation = plant;
  } else if (simulated) {
    s.simulation = host::SimulatedPlant{};
  }
  return r;
}

host::Outcome Invalid(std::string message) {
  return host::Outcome{Status::kInvalidArgument, std::move(message), {}};
}

}  // namespace

host::Outcome CalibrateFromJson(host::Device* device, const std::string& rig,
                                const nlohmann::json& options, nlohmann::ordered_json* summary) {
  const bool simulated = rig == "sim";
  Request r;
  try {
    r = Parse(options, simulated);
  } catch (const std::exception& e) {
    return Invalid(e.what());
  }
  host::Result<BoardRig> opened{BoardRig{}};
  if (simulated) {
    opened =
        OpenSimulatedRig(r.sim_config, r.session.finger, r.sim_speed, *r.session.simulation, 0);
  } else {
    if (device == nullptr) return Invalid("a rig file calibrates beside an open device");
    const auto description = LoadRigDescription(rig);
    if (!description.ok()) return Invalid(description.message);
    opened = OpenBoardRig(*device, description.value);
  }
  if (!opened.ok()) return opened.outcome();
  if (simulated) r.session.simulation = opened.value.simulation;  // as the simulator runs it
  host::Device& board = *opened.value.device;
  const host::Result<std::string> serial = ReadActuatorSerial(board, r.session.finger);
  if (!serial.ok()) return serial.outcome();
  const bool jamming =
      board.info().fingers[r.session.finger].kind == protocol::FingerKind::kJamming;
  Session session(opened.value.rig(), serial.value, board.info().board_id, jamming, r.session);
  if (host::Outcome o = session.Calibrate(nullptr); !o.ok()) return o;
  if (r.apply) {
    host::Outcome o = board.ApplyCalibration(r.session.finger, session.result().file);
    if (!o.ok()) return o;
  }
  *summary = session.Summary(r.apply, 0);
  return {};
}

}  // namespace palpa::calibration
