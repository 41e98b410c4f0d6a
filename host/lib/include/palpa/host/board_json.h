// A board as JSON — its identity, lines, fingers and diagnostics — as `palpa info` and `palpa diag`
// print it and `palpa serve` answers it: numbered as the caller numbers, no second line as null.
#pragma once

#include <vector>

#include <nlohmann/json.hpp>

#include "palpa/host/board_curves.h"
#include "palpa/host/link.h"
#include "palpa/host/stiffness_map.h"
#include "palpa/protocol/messages_bootstrap.h"
#include "palpa/protocol/messages_report.h"

namespace palpa::host {

/// [{"line": 1, "kind", "sensor", "limit_min_pa", "limit_max_pa"}, ...]
nlohmann::ordered_json LinesJson(const protocol::HelloReply& board, unsigned number_from = 1);

/// [{"finger": 1, "kind", "unit", "line_a", "line_b" (null: none), "curve"}, ...]; "curve" (the
/// source of each finger's curve) only when `curves` is given.
nlohmann::ordered_json FingersJson(const protocol::HelloReply& board,
                                   const std::vector<FingerCurves>* curves = nullptr,
                                   unsigned number_from = 1);

/// What the configuration's state means for a reset: "saved", "factory default", or changed and
/// what a reset returns to.
std::string ConfigStateText(const protocol::Diagnostics& diag);

/// {"kind", "id", "firmware", "protocol", "catalog_hash", "catalog_matches", ..., "faults"}: the
/// board's identity from its Hello, its configuration's state and its faults from `diag` (read
/// now, not at Hello).
nlohmann::ordered_json BoardIdentityJson(const protocol::HelloReply& board,
                                         const protocol::Diagnostics& diag, bool catalog_matches);

/// The lines, numbered from `number_from`, whose shaped steps fell back to unshaped ones.
std::vector<int> ShapingFellBackLines(const protocol::Diagnostics& diag, unsigned number_from);

/// {"reset_cause", "boot_count", "faults_latched", ..., "history", "loop", "link"}: the board's
/// diagnostics, its loop statistics and the host link's counters; fault details name lines
/// numbered from `number_from`.
nlohmann::ordered_json DiagnosticsJson(const protocol::Diagnostics& diag,
                                       const protocol::LoopStats& stats, const LinkCounters& link,
                                       unsigned number_from);

/// [{"finger", "file", "board", "disagreement", "at_kpa", "residual", "unit", "message"}, ...]:
/// Device::curve_warnings() with fingers numbered from `number_from`; disagreement null where the
/// two curves share no drive.
nlohmann::ordered_json CurveWarningsJson(const std::vector<CurveWarning>& warnings,
                                         unsigned number_from);

}  // namespace palpa::host
