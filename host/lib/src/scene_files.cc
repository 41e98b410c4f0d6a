// Tissue files: the palpa-tissue JSON grid read and written, CSV force matrices read, every
// refusal naming the file, the field or line, and what was expected.
#include "palpa/host/scene_files.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "number_text.h"
#include "palpa/host/json_check.h"

namespace palpa::host {
namespace {

/// A grid of rows × columns numbers at `path` ("values", "depths[2].force_n"), as the map's shape
/// says when it is known (nx, ny non-zero), else setting it.
std::vector<double> ParseGrid(const nlohmann::json& j, const std::string& path, size_t* nx,
                              size_t* ny) {
  if (!j.is_array()) throw JsonInvalid(path + ": must be an array of rows");
  if (j.size() < 2 || j.size() > kMaxTissuePoints || (*ny != 0 && j.size() != *ny)) {
    throw JsonInvalid(path + ": has " + std::to_string(j.size()) + " rows, needs " +
                      (*ny != 0 ? std::to_string(*ny) : "2 … " + std::to_string(kMaxTissuePoints)));
  }
  std::vector<double> grid;
  for (size_t r = 0; r < j.size(); ++r) {
    const std::string row = path + "[" + std::to_string(r) + "]";
    const nlohmann::json& values = j[r];
    if (!values.is_array()) throw JsonInvalid(row + ": must be an array of numbers");
    if (values.size() < 2 || values.size() > kMaxTissuePoints ||
        (*nx != 0 && values.size() != *nx)) {
      throw JsonInvalid(row + ": has " + std::to_string(values.size()) + " values, needs " +
                        (*nx != 0 ? std::to_string(*nx) + " (as row 0 of values)"
                                  : "2 … " + std::to_string(kMaxTissuePoints)));
    }
    if (*nx == 0) *nx = values.size();
    for (size_t c = 0; c < values.size(); ++c) {
      if (!values[c].is_number())
        throw JsonInvalid(row + "[" + std::to_string(c) + "]: must be a number");
      grid.push_back(values[c].get<double>());
    }
  }
  *ny = j.size();
  return grid;
}

nlohmann::json GridJson(const std::vector<double>& grid, size_t nx, size_t ny) {
  nlohmann::json rows = nlohmann::json::array();
  for (size_t j = 0; j < ny; ++j) {
    rows.push_back(std::vector<double>(grid.begin() + static_cast<long>(j * nx),
                                       grid.begin() + static_cast<long>((j + 1) * nx)));
  }
  return rows;
}

/// The extent stated along one side must be what the points and the pitch make.
void CheckExtent(const nlohmann::json& extent, size_t side, size_t points, double pitch) {
  const std::string at = "extent_mm[" + std::to_string(side) + "]";
  if (!extent[side].is_number()) throw JsonInvalid(at + ": must be a number");
  const double stated = extent[side].get<double>();
  const double made = static_cast<double>(points - 1) * pitch;
  if (!(std::fabs(stated - made) <= 1e-6 * std::max(1.0, made))) {
    throw JsonInvalid(at + ": " + Num(stated) + " mm is not (points − 1) · pitch = " +
                      std::to_string(points - 1) + " · " + Num(pitch) + " = " + Num(made) + " mm");
  }
}

TissueMap Parse(const nlohmann::json& j) {
  const JsonObject doc(
      j, "",
      {"schema", "schema_version", "name", "unit", "pitch_mm", "extent_mm", "values", "depths"});
  if (doc.Text("schema") != "palpa-tissue") throw JsonInvalid("schema: must be \"palpa-tissue\"");
  doc.Integer("schema_version", 1, 1);
  TissueMap map;
  map.name = doc.Text("name");
  map.unit = doc.Text("unit");
  if (doc.At("pitch_mm").is_array()) {
    const nlohmann::json& p = doc.List("pitch_mm", 2, 2);
    for (size_t k = 0; k < 2; ++k) {
      const std::string at = doc.Item("pitch_mm", k);
      if (!p[k].is_number() || !(p[k].get<double>() > 0 && p[k].get<double>() <= 1000))
        throw JsonInvalid(at + ": must be a number of mm in (0, 1000]");
    }
    map.pitch_x_mm = p[0].get<double>();
    map.pitch_y_mm = p[1].get<double>();
  } else {
    map.pitch_x_mm = map.pitch_y_mm = doc.Number("pitch_mm", 1e-6, 1000);
  }
  map.values = ParseGrid(doc.At("values"), "values", &map.nx, &map.ny);
  const nlohmann::json& extent = doc.List("extent_mm", 2, 2);
  CheckExtent(extent, 0, map.nx, map.pitch_x_mm);
  CheckExtent(extent, 1, map.ny, map.pitch_y_mm);
  if (doc.Has("depths")) {
    const nlohmann::json& depths = doc.List("depths", 1, kMaxTissueDepths);
    for (size_t l = 0; l < depths.size(); ++l) {
      const std::string at = doc.Item("depths", l);
      const JsonObject layer(depths[l], at, {"depth_mm", "force_n"});
      ForceLayer f;
      f.depth_mm = layer.Number("depth_mm", 1e-6, 100);
      if (!map.layers.empty() && f.depth_mm <= map.layers.back().depth_mm) {
        throw JsonInvalid(at + ".depth_mm: " + Num(f.depth_mm) + " is not deeper than the layer " +
                          "before (" + Num(map.layers.back().depth_mm) + "): depths rise");
      }
      f.force_n = ParseGrid(layer.At("force_n"), at + ".force_n", &map.nx, &map.ny);
      map.layers.push_back(std::move(f));
    }
  }
  return map;
}

}  // namespace

Result<TissueMap> ParseTissue(const std::string& text) {
  return ParseJsonWith<TissueMap>(text, Parse);
}

Result<TissueMap> LoadTissue(const std::string& path) {
  return ReadAndParse(path, kTissueFileLimits, ParseTissue);
}

Result<std::string> SerializeTissue(const TissueMap& map) {
  if (const Outcome ok = CheckTissue(map); !ok.ok()) return ok;
  if (map.name.empty() || map.unit.empty())
    return {Status::kInvalidArgument, "a tissue needs a name and a unit"};
  nlohmann::json j = {
      {"schema", "palpa-tissue"}, {"schema_version", 1}, {"name", map.name}, {"unit", map.unit}};
  j["pitch_mm"] = map.pitch_x_mm == map.pitch_y_mm
                      ? nlohmann::json(map.pitch_x_mm)
                      : nlohmann::json::array({map.pitch_x_mm, map.pitch_y_mm});
  j["extent_mm"] = {map.extent_x_mm(), map.extent_y_mm()};
  j["values"] = GridJson(map.values, map.nx, map.ny);
  if (map.has_depth()) {
    nlohmann::json depths = nlohmann::json::array();
    for (const ForceLayer& l : map.layers)
      depths.push_back(
          {{"depth_mm", l.depth_mm}, {"force_n", GridJson(l.force_n, map.nx, map.ny)}});
    j["depths"] = depths;
  }
  return j.dump() + "\n";
}

std::vector<std::pair<size_t, std::string>> CsvDataLines(const std::string& text) {
  std::vector<std::pair<size_t, std::string>> lines;
  size_t line_no = 0;
  for (size_t at = 0; at <= text.size();) {
    size_t end = text.find('\n', at);
    if (end == std::string::npos) end = text.size();
    std::string line = text.substr(at, end - at);
    at = end + 1;
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.find_first_not_of(" \t") == std::string::npos || line[0] == '#') continue;
    lines.emplace_back(line_no, std::move(line));
  }
  return lines;
}

Result<std::vector<double>> ParseCsvNumbers(const std::string& line, const std::string& where,
                                            size_t max_values) {
  std::vector<double> row;
  for (size_t from = 0;;) {
    const size_t comma = std::min(line.find(',', from), line.size());
    std::string cell = line.substr(from, comma - from);
    cell.erase(0, cell.find_first_not_of(" \t"));
    cell.erase(cell.find_last_not_of(" \t") + 1);
    char* stop = nullptr;
    errno = 0;
    const double v = std::strtod(cell.c_str(), &stop);
    if (cell.empty() || *stop != '\0' || errno == ERANGE || !std::isfinite(v)) {
      return {Status::kInvalidArgument, where + ", value " + std::to_string(row.size() + 1) +
                                            ": \"" + cell + "\" is not a number"};
    }
    if (row.size() == max_values) {
      return {Status::kInvalidArgument,
              where + ": more than " + std::to_string(max_values) + " values"};
    }
    row.push_back(v);
    if (comma == line.size()) return row;
    from = comma + 1;
  }
}

Result<std::vector<std::vector<double>>> ParseForceMatrix(const std::string& text,
                                                          const std::string& source) {
  using Rows = Result<std::vector<std::vector<double>>>;
  std::vector<std::vector<double>> rows;
  size_t first_line = 0;
  for (const auto& [line_no, line] : CsvDataLines(text)) {
    const std::string where = source + ": line " + std::to_string(line_no);
    auto parsed = ParseCsvNumbers(line, where, kMaxTissuePoints);
    if (!parsed.ok()) return parsed.outcome();
    std::vector<double> row = std::move(parsed.value);
    if (!rows.empty() && row.size() != rows[0].size()) {
      return Rows(Status::kInvalidArgument, where + ": " + std::to_string(row.size()) +
                                                " values where line " + std::to_string(first_line) +
                                                " has " + std::to_string(rows[0].size()));
    }
    if (rows.size() == kMaxTissuePoints) {
      return Rows(Status::kInvalidArgument,
                  where + ": more than " + std::to_string(kMaxTissuePoints) + " scan lines");
    }
    if (rows.empty()) first_line = line_no;
    rows.push_back(std::move(row));
  }
  if (rows.size() < 2 || rows[0].size() < 2) {
    return Rows(Status::kInvalidArgument,
                source + ": a force matrix needs at least 2 scan lines of at least 2 values");
  }
  return rows;
}

Result<TissueMap> LoadForceMatrices(const ForceMatrixScan& scan) {
  TissueMap map;
  map.name = scan.name.empty() ? "force matrices" : scan.name;
  map.unit = "N/mm";
  map.pitch_x_mm = scan.along_line_pitch_mm;
  map.pitch_y_mm = scan.line_pitch_mm;
  if (scan.files.empty() || scan.files.size() > kMaxTissueDepths) {
    return {Status::kInvalidArgument, "a scan has 1 … " + std::to_string(kMaxTissueDepths) +
                                          " force matrices, one per depth, not " +
                                          std::to_string(scan.files.size())};
  }
  for (const ForceMatrixFile& file : scan.files) {
    const double previous = map.layers.empty() ? 0 : map.layers.back().depth_mm;
    if (!std::isfinite(file.depth_mm) || file.depth_mm <= previous || file.depth_mm > 100) {
      return {Status::kInvalidArgument, file.path + ": depth " + Num(file.depth_mm) +
                                            " mm: depths rise, each above " + Num(previous) +
                                            " and at most 100 mm"};
    }
    const Result<std::string> text = ReadFileWhole(file.path, kForceMatrixLimits);
    if (!text.ok()) return text.outcome();
    const auto rows = ParseForceMatrix(text.value, file.path);
    if (!rows.ok()) return rows.outcome();
    const size_t nx = rows.value[0].size(), ny = rows.value.size();
    if (!map.layers.empty() && (nx != map.nx || ny != map.ny)) {
      return {Status::kInvalidArgument, file.path + ": " + std::to_string(ny) + " lines of " +
                                            std::to_string(nx) + " values, where " +
                                            scan.files[0].path + " has " + std::to_string(map.ny) +
                                            " of " + std::to_string(map.nx)};
    }
    map.nx = nx;
    map.ny = ny;
    ForceLayer layer{file.depth_mm, {}};
    for (const auto& row : rows.value)
      layer.force_n.insert(layer.force_n.end(), row.begin(), row.end());
    map.layers.push_back(std::move(layer));
  }
  map.values.assign(map.nx * map.ny, 0.0);
  double dd = 0;
  for (const ForceLayer& l : map.layers) dd += l.depth_mm * l.depth_mm;
  for (size_t k = 0; k < map.values.size(); ++k) {
    double fd = 0;
    for (const ForceLayer& l : map.layers) fd += l.force_n[k] * l.depth_mm;
    map.values[k] = dd > 0 ? fd / dd : 0;
  }
  if (Outcome ok = CheckTissue(map); !ok.ok()) {
    ok.message = "force matrices " + scan.files[0].path + " …: " + ok.message;
    return ok;
  }
  return map;
}

}  // namespace palpa::host
