// A board's lines and fingers as JSON for people: numbered from 1, no second line as null.
#pragma once

#include <vector>

#include <nlohmann/json.hpp>

#include "palpa/host/board_curves.h"
#include "palpa/host/stiffness_map.h"
#include "palpa/protocol/messages_bootstrap.h"

namespace palpa::host {

/// [{"line": 1, "kind", "sensor", "limit_min_pa", "limit_max_pa"}, ...]
nlohmann::ordered_json LinesJson(const protocol::HelloReply& board);

/// [{"finger": 1, "kind", "unit", "line_a", "line_b" (null: none), "curve"}, ...]; "curve" (the
/// source of each finger's curve) only when `curves` is given.
nlohmann::ordered_json FingersJson(const protocol::HelloReply& board,
                                   const std::vector<FingerCurves>* curves = nullptr);

/// [{"finger", "file", "board", "disagreement", "at_kpa", "residual", "unit", "message"}, ...]:
/// Device::curve_warnings() with fingers numbered from `number_from`; disagreement null where the
/// two curves share no drive.
nlohmann::ordered_json CurveWarningsJson(const std::vector<CurveWarning>& warnings,
                                         unsigned number_from);

}  // namespace palpa::host
