// A board's lines and fingers as JSON, numbered as people number them.
#include "palpa/host/board_json.h"

namespace palpa::host {

namespace pp = palpa::protocol;
using nlohmann::ordered_json;

ordered_json LinesJson(const pp::HelloReply& b) {
  ordered_json lines = ordered_json::array();
  for (uint8_t i = 0; i < b.line_count; ++i) {
    lines.push_back({{"line", i + 1},
                     {"kind", pp::kLineKindNames[static_cast<int>(b.lines[i].kind)]},
                     {"sensor", b.lines[i].has_sensor},
                     {"limit_min_pa", b.lines[i].limit_min_pa},
                     {"limit_max_pa", b.lines[i].limit_max_pa}});
  }
  return lines;
}

ordered_json FingersJson(const pp::HelloReply& b, const std::vector<FingerCurves>* curves) {
  ordered_json fingers = ordered_json::array();
  for (uint8_t f = 0; f < b.finger_count; ++f) {
    const pp::FingerSummary& finger = b.fingers[f];
    ordered_json j = {{"finger", f + 1},
                      {"kind", pp::kFingerKindNames[static_cast<int>(finger.kind)]},
                      {"unit", OutputUnitName(finger.kind)},
                      {"line_a", finger.line_a + 1},
                      {"line_b", finger.line_b == pp::kNoLine ? ordered_json(nullptr)
                                                              : ordered_json(finger.line_b + 1)}};
    if (curves != nullptr && f < curves->size()) j["curve"] = (*curves)[f].source;
    fingers.push_back(j);
  }
  return fingers;
}

ordered_json CurveWarningsJson(const std::vector<CurveWarning>& warnings, unsigned number_from) {
  ordered_json list = ordered_json::array();
  for (const CurveWarning& w : warnings) {
    list.push_back({{"finger", w.finger + number_from},
                    {"file", w.file},
                    {"board", w.board},
                    {"disagreement", w.overlap ? ordered_json(w.disagreement) : ordered_json()},
                    {"at_kpa", w.at_pa / 1000},
                    {"residual", w.residual},
                    {"unit", w.unit},
                    {"message", w.message}});
  }
  return list;
}

}  // namespace palpa::host
