// palpa render's record and live status: a CSV row per rendered sample (the input, the place
// rendered when predicting, the board's time, each finger's touching, value and target), the
// path for the SVG, and the terminal's status line.
#pragma once

#include <atomic>
#include <cstdint>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "palpa/host/scene_file.h"
#include "palpa/host/scene_render.h"

namespace palpa::cli {

/// "OUT" → "OUT.svg" beside it (an .csv ending replaced).
inline std::string SvgPath(const std::string& record) {
  const size_t dot = record.rfind(".csv");
  return (dot != std::string::npos && dot + 4 == record.size() ? record.substr(0, dot) : record) +
         ".svg";
}

/// The record's rows and the terminal's status line, one per rendered sample.
struct RenderRecord {
  std::string csv;
  std::vector<std::pair<double, double>> path;
  std::atomic<uint64_t> board_us{0};
  bool live = false, hand = true, predicted = false;
  size_t fed = 0;

  void Header(const host::SceneSpec& spec) {
    csv = hand ? "time_s,x_mm,y_mm,force_n" : "time_s";
    if (predicted) csv += ",rendered_x_mm,rendered_y_mm";
    csv += ",board_time_us";
    for (uint8_t f : spec.board_fingers) {
      const std::string n = std::to_string(f + 1);
      csv += ",finger" + n + "_touching,finger" + n + "_value,finger" + n + "_target";
    }
    csv += "\n";
  }
  void Row(const host::SceneInput& s, const host::SceneInput* rendered,
           const std::vector<host::FingerRender>& renders) {
    ++fed;
    char row[200];
    if (hand) {
      path.emplace_back(s.x_mm, s.y_mm);
      std::snprintf(row, sizeof(row), "%.6f,%.4f,%.4f,%.4f", s.time_s, s.x_mm, s.y_mm, s.force_n);
    } else {
      std::snprintf(row, sizeof(row), "%.6f", s.time_s);
    }
    csv += row;
    if (predicted && rendered != nullptr) {
      std::snprintf(row, sizeof(row), ",%.4f,%.4f", rendered->x_mm, rendered->y_mm);
      csv += row;
    }
    std::snprintf(row, sizeof(row), ",%llu", static_cast<unsigned long long>(board_us.load()));
    csv += row;
    std::string status;
    for (const host::FingerRender& r : renders) {
      std::snprintf(row, sizeof(row), ",%d,%.6g,%.6g", r.touching ? 1 : 0, r.value,
                    r.mapped.target / 1000.0);
      csv += row;
      std::snprintf(row, sizeof(row), "  %5.3f", r.mapped.target / 1000.0);
      status += row;
    }
    csv += "\n";
    if (live) {
      if (hand)
        std::printf("\r%7.3f s  x %6.1f  y %6.1f mm  %4.2f N  targets%s", s.time_s, s.x_mm, s.y_mm,
                    s.force_n, status.c_str());
      else
        std::printf("\r%7.3f s  targets%s", s.time_s, status.c_str());
      std::fflush(stdout);
    }
  }
};

}  // namespace palpa::cli
