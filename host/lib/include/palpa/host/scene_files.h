// Tissue files: a JSON grid (schema palpa-tissue) read and written, and CSV force matrices (one
// file per indentation depth, as the thesis's sliding-indentation scans) read into a stiffness map.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "palpa/host/file_read.h"
#include "palpa/host/outcome.h"
#include "palpa/host/scene_tissue.h"

namespace palpa::host {

/// A 1 024 × 1 024 grid of full-precision numbers is about 20 MiB; the thesis's largest map with
/// its six depth layers about 0.5 MiB.
inline constexpr FileLimits kTissueFileLimits{"tissue file", 32 * 1024 * 1024};
/// One depth's force matrix: 1 024 × 1 024 values of up to 16 characters.
inline constexpr FileLimits kForceMatrixLimits{"force matrix", 16 * 1024 * 1024};

/// A tissue from JSON text (schema "palpa-tissue", version 1):
///   {"schema": "palpa-tissue", "schema_version": 1, "name": "...", "unit": "kPa",
///    "pitch_mm": 0.5 | [x, y], "extent_mm": [x, y],
///    "values": [[row at y = 0 …], [row at y = pitch_y …], …],
///    "depths": [{"depth_mm": 2, "force_n": [[…], …]}, …]}   (optional)
/// The extent must be (points − 1) · pitch along each side. A bad document is invalid_argument
/// naming the field by its path ("values[3][7]: must be a number").
Result<TissueMap> ParseTissue(const std::string& text);
Result<TissueMap> LoadTissue(const std::string& path);
/// The JSON text ParseTissue reads back to the same map (every double exactly).
Result<std::string> SerializeTissue(const TissueMap& map);

/// One CSV force matrix and the depth it was scanned at.
struct ForceMatrixFile {
  std::string path;
  double depth_mm = 0;
};

/// How a set of force matrices was scanned: the pitch along a scan line (between a row's values,
/// x) and between lines (between rows, y), and one file per depth.
struct ForceMatrixScan {
  std::string name;
  double along_line_pitch_mm = 0;
  double line_pitch_mm = 0;
  std::vector<ForceMatrixFile> files;
};

/// The lines of a CSV text that hold data, with their 1-based numbers: blank lines and lines
/// starting with '#' skipped, a CR before the LF dropped.
std::vector<std::pair<size_t, std::string>> CsvDataLines(const std::string& text);

/// One CSV line of numbers, at most `max_values` of them; `where` names it in errors ("PATH: line
/// 4" + ", value 17: \"1.2x\" is not a number"). Spaces around a value are allowed; an empty
/// value, one no double holds, inf and nan are not.
Result<std::vector<double>> ParseCsvNumbers(const std::string& line, const std::string& where,
                                            size_t max_values);

/// A force matrix's text: rows of comma-separated numbers (one scan line per row), all rows the
/// same length; blank lines and lines starting with '#' are skipped. `source` names the text in
/// errors ("PATH: line 4, value 17: \"1.2x\" is not a number").
Result<std::vector<std::vector<double>>> ParseForceMatrix(const std::string& text,
                                                          const std::string& source);

/// Reads every file of a scan (each within kForceMatrixLimits, all of one shape, depths rising)
/// into a map whose layers are the matrices and whose values are each point's stiffness in N/mm:
/// the least-squares slope through the origin of force against depth, Σ f·d / Σ d² (Hooke's law,
/// as the thesis reads a jamming finger's stiffness).
Result<TissueMap> LoadForceMatrices(const ForceMatrixScan& scan);

}  // namespace palpa::host
