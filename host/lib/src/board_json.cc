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

}  // namespace palpa::host
