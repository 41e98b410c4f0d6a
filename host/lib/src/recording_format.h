// The recording's CSV: its JSON header, its columns and its rows, in the wide or long layout.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "palpa/host/device.h"

namespace palpa::host::recording {

/// The first line's JSON (after "# "): board, configuration, layout, units, numbering, clock.
nlohmann::ordered_json Header(const pp::HelloReply& board, RecordLayout layout,
                              const std::vector<FingerCurves>& curves);

/// The column names, comma-separated.
std::string Columns(const pp::HelloReply& board, RecordLayout layout);

/// UTC, ISO 8601 with microseconds: "2026-11-25T17:49:05.123456Z".
std::string UtcText(double unix_seconds);

/// The rows of one tick: one (wide), or one per line (long), each ending in a newline.
/// `lines` are the tick's line_count samples.
void AppendRows(std::string& out, const pp::HelloReply& board, RecordLayout layout,
                double unix_seconds, uint64_t board_us, uint32_t faults,
                const pp::LineSample* lines, const std::vector<FingerCurves>& curves);

}  // namespace palpa::host::recording
