// libFuzzer target: the files the host library reads — calibration files, update packages and
// configuration files.
//
// Whatever the bytes, a parser must return a result or an error that says what is wrong (never
// throw, crash or invoke undefined behaviour), and what it accepts must survive a round trip:
// a calibration serialises, parses back and serialises to the same text; a package writes and
// reads back to the same images; a configuration prints and reads back to the same one. Input byte
// 0 picks the mode:
//   0  raw text as a calibration file;
//   1  a valid calibration file with one JSON value replaced (any field, any type or magnitude);
//   2  a valid calibration file with bytes overwritten or cut short;
//   3  raw bytes as an update package;
//   4  a valid update package with bytes overwritten or cut short;
//   5  a compiled-in configuration as `palpa config show` prints it, one value replaced or removed.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iterator>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "example_calibration.h"
#include "fuzz_input.h"
#include "palpa/core/board_configs.h"
#include "palpa/host/calibration_file.h"
#include "palpa/host/config_json.h"
#include "palpa/host/firmware_image.h"

namespace pc = palpa::core;
namespace ph = palpa::host;
namespace pp = palpa::protocol;
using nlohmann::json;

namespace {

using Bytes = palpa::testing::FuzzInput;

[[noreturn]] void Fail(const char* what, const std::string& detail) {
  std::fprintf(stderr, "host files fuzz: %s: %s\n", what, detail.c_str());
  std::abort();
}

const std::string& ValidCalibrationText() {
  static const std::string text = [] {
    std::string error;
    const auto s = ph::SerializeCalibration(palpa::testing::ExampleCalibration(), &error);
    if (!s) Fail("the reference calibration does not serialise", error);
    return *s;
  }();
  return text;
}

/// Parse, and check what comes back: an error with a reason, or a calibration that round-trips.
void CheckCalibration(const std::string& text) {
  std::string error;
  const auto parsed = ph::ParseCalibration(text, &error);
  if (!parsed) {
    if (error.empty()) Fail("a refused calibration came without a reason", text.substr(0, 200));
    return;
  }
  const auto written = ph::SerializeCalibration(*parsed, &error);
  if (!written) Fail("an accepted calibration does not serialise", error);
  const auto again = ph::ParseCalibration(*written, &error);
  if (!again) Fail("a serialised calibration does not parse back", error);
  const auto rewritten = ph::SerializeCalibration(*again, &error);
  if (!rewritten || *rewritten != *written) Fail("a calibration changes in a round trip", *written);
}

/// Any JSON value: integers and floats of every magnitude, strings, null, booleans, containers.
json AnyValue(Bytes& in) {
  const uint8_t kind = in.Byte();
  static const double kEdges[] = {
      0.0,          -0.0,         1e-300,        1e-45,        3.5e38, -3.5e38, 1e300, -1e300,
      2147483647.0, 2147483648.0, -2147483649.0, 4294967296.0, 9.3e18, -9.3e18, 0.5,   -1.0};
  switch (kind % 9) {
    case 0:
      return static_cast<int64_t>(in.Word64());
    case 1:
      return in.Word64();  // unsigned 64-bit
    case 2: {
      const uint64_t bits = in.Word64();
      double d;
      std::memcpy(&d, &bits, sizeof(d));
      return std::isfinite(d) ? json(d) : json(nullptr);  // JSON has no NaN or infinity
    }
    case 3:
      return kEdges[in.Byte() % (sizeof(kEdges) / sizeof(kEdges[0]))];
    case 4: {
      std::string s;
      for (uint8_t n = in.Byte() % 16; n > 0; --n) s.push_back(static_cast<char>(in.Byte()));
      return s;
    }
    case 5:
      return nullptr;
    case 6:
      return (kind & 0x80) != 0;
    case 7:
      return json::array();
    default:
      return json::object();
  }
}

/// One leaf of `j` (picked by its JSON pointer) replaced by any value, or removed.
void EditOneLeaf(Bytes& in, json& j) {
  const json flat = j.flatten();
  auto leaf = flat.begin();
  std::advance(leaf, (in.Byte() | in.Byte() << 8) % flat.size());
  const json::json_pointer where(leaf.key());
  if (in.Byte() % 8 == 0) {
    json& parent = j[where.parent_pointer()];
    if (parent.is_object()) parent.erase(where.back());
    if (parent.is_array()) parent.erase(std::stoul(where.back()));
  } else {
    j[where] = AnyValue(in);
  }
}

/// A configuration file onto a compiled-in configuration, as `palpa config load` applies it:
/// refused with the field's path, or accepted and then printed and read back unchanged; the
/// firmware's validation must then judge it without crashing.
void CheckConfigJson(const pc::BoardConfig& base, const json& file) {
  pc::BoardConfig applied = base;
  try {
    ph::ApplyConfigJson(file, applied);
  } catch (const std::exception& e) {
    if (std::strlen(e.what()) == 0)
      Fail("a refused configuration came without a reason", file.dump());
    return;
  }
  const json printed = ph::ConfigToJson(applied);
  pc::BoardConfig again = base;
  ph::ApplyConfigJson(printed, again);
  if (ph::ConfigToJson(again) != printed)
    Fail("a configuration changes when printed and read back", printed.dump());
  pc::ConfigError error;
  (void)pc::ValidateConfig(applied, &error);
}

void CheckPackage(const std::vector<uint8_t>& bytes) {
  std::string error;
  const auto package = ph::ReadPackage(bytes, &error);
  if (!package) {
    if (error.empty())
      Fail("a refused package came without a reason", std::to_string(bytes.size()));
    return;
  }
  const auto again = ph::ReadPackage(ph::WritePackage(*package), &error);
  if (!again) Fail("an accepted package does not read back once written", error);
  if (again->slot_image != package->slot_image) Fail("a package changes in a round trip", "");
}

const std::vector<uint8_t>& ValidPackage() {
  static const std::vector<uint8_t> bytes = [] {
    ph::UpdatePackage p;
    for (uint8_t slot = 0; slot < 2; ++slot) {
      ph::ImageSpec spec;
      spec.body.assign(600, static_cast<uint8_t>(0x5A + slot));
      spec.slot = slot;
      spec.version_minor = 3;
      spec.rollback_counter = 2;
      spec.board_kind = pp::BoardKind::kSim;
      p.slot_image[slot] = ph::BuildImage(spec);
    }
    return ph::WritePackage(p);
  }();
  return bytes;
}

/// Overwrites a few bytes at chosen places and may cut the end off.
template <class Container>
void Damage(Bytes& in, Container& c) {
  for (uint8_t n = in.Byte() % 8; n > 0 && !c.empty(); --n) {
    const size_t at = (in.Byte() | in.Byte() << 8 | in.Byte() << 16) % c.size();
    c[at] = static_cast<typename Container::value_type>(in.Byte());
  }
  const uint8_t cut = in.Byte();
  if (cut < 32 && !c.empty()) c.resize(c.size() * cut / 32);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  Bytes in(data, size);
  switch (in.Byte() % 6) {
    case 0:
      CheckCalibration(in.Rest());
      break;
    case 1: {
      json j = json::parse(ValidCalibrationText());
      EditOneLeaf(in, j);
      // Invalid UTF-8 in a string value becomes U+FFFD (raw bytes reach the parser in mode 0).
      CheckCalibration(j.dump(-1, ' ', false, json::error_handler_t::replace));
      break;
    }
    case 2: {
      std::string text = ValidCalibrationText();
      Damage(in, text);
      CheckCalibration(text);
      break;
    }
    case 3: {
      const std::string rest = in.Rest();
      CheckPackage(std::vector<uint8_t>(rest.begin(), rest.end()));
      break;
    }
    case 5: {
      const pc::BoardConfig& base = *pc::kBoardConfigs[in.Byte() % pc::kBoardConfigCount].config;
      json file = ph::ConfigToJson(base);
      EditOneLeaf(in, file);
      CheckConfigJson(base, file);
      break;
    }
    default: {
      std::vector<uint8_t> bytes = ValidPackage();
      Damage(in, bytes);
      CheckPackage(bytes);
      break;
    }
  }
  return 0;
}
