// libFuzzer target: the files the host reads — calibration files, configuration files, rig
// files, calibration journals, stimulus sets, scene kinds (fuzz_scene_files.cc) and update
// packages.
//
// Whatever the bytes, a reader must return a result or an error that says what is wrong and
// where (never throw, crash or invoke undefined behaviour, and never hand on a JSON library's own
// "[json.exception..." message: that would be a value used without its type checked), and what it
// accepts must survive a round trip where the kind has one: a calibration serialises, parses back
// and serialises to the same text; a package writes and reads back to the same images; a
// configuration prints and reads back to the same one. Input byte 0 picks the kind (calibration,
// configuration, rig, journal, stimulus set, scene kind, package) and how its valid reference is
// changed (a calibration's reference is the one written now or a schema version 1 file of either
// finger kind):
//   raw bytes; one JSON value replaced by any type or magnitude, or removed; one number in the
//   text replaced by a literal no double holds or no integer fits ("1e400", "-1e999",
//   "99999999999999999999", ...); bytes overwritten or the text cut short.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iterator>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "development_signer.h"
#include "example_calibration.h"
#include "fuzz_host_files.h"
#include "fuzz_input.h"
#include "palpa/calibration/calibration_protocol.h"
#include "palpa/calibration/rig_file.h"
#include "palpa/core/board_configs.h"
#include "palpa/host/calibration_file.h"
#include "palpa/host/config_json.h"
#include "palpa/host/firmware_image.h"
#include "palpa/host/json_check.h"
#include "palpa/host/stimulus_set.h"

namespace cal = palpa::calibration;
namespace pc = palpa::core;
namespace ph = palpa::host;
namespace pp = palpa::protocol;
using nlohmann::json;

namespace palpa::testing::files_fuzz {

void Fail(const char* what, const std::string& detail) {
  std::fprintf(stderr, "host files fuzz: %s: %s\n", what, detail.c_str());
  std::abort();
}

void CheckReason(const char* kind, const std::string& error, const std::string& text) {
  if (error.empty())
    Fail((std::string("a refused ") + kind + " came without a reason").c_str(),
         text.substr(0, 200));
  if (error.find("[json.exception") != std::string::npos)
    Fail((std::string("a ") + kind + " was refused with the library's message").c_str(), error);
}

}  // namespace palpa::testing::files_fuzz

namespace {

using namespace palpa::testing::files_fuzz;

const std::string& ValidCalibrationText() {
  static const std::string text = [] {
    const auto s = ph::SerializeCalibration(palpa::testing::ExampleCalibration());
    if (!s.ok()) Fail("the reference calibration does not serialise", s.message);
    return s.value;
  }();
  return text;
}

/// A valid calibration to change: the reference as written now, or a file of schema version 1.
const std::string& SomeValidCalibrationText(uint8_t pick) {
  static const std::string v1[2] = {
      ph::ReadFileWhole(PALPA_TEST_DATA_DIR "/calibration_v1_pneumatic.json",
                        ph::kCalibrationFileLimits)
          .value,
      ph::ReadFileWhole(PALPA_TEST_DATA_DIR "/calibration_v1_jamming.json",
                        ph::kCalibrationFileLimits)
          .value};
  return pick % 3 == 0 ? ValidCalibrationText() : v1[pick % 3 - 1];
}

/// Parse, and check what comes back: an error with a reason, or a calibration that round-trips.
void CheckCalibration(const std::string& text) {
  const auto parsed = ph::ParseCalibration(text);
  if (!parsed.ok()) {
    CheckReason("calibration", parsed.message, text);
    return;
  }
  const auto written = ph::SerializeCalibration(parsed.value);
  if (!written.ok()) Fail("an accepted calibration does not serialise", written.message);
  const auto again = ph::ParseCalibration(written.value);
  if (!again.ok()) Fail("a serialised calibration does not parse back", again.message);
  const auto rewritten = ph::SerializeCalibration(again.value);
  if (!rewritten.ok() || rewritten.value != written.value)
    Fail("a calibration changes in a round trip", written.value);
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

/// A configuration file onto a compiled-in configuration, as `palpa config load` reads and
/// applies it: refused with the field's path, or accepted and then printed and read back
/// unchanged; the firmware's validation must then judge it without crashing.
void CheckConfigText(const pc::BoardConfig& base, const std::string& text) {
  const auto file = ph::ParseJson(text);
  if (!file.ok()) {
    CheckReason("configuration", file.message, text);
    return;
  }
  pc::BoardConfig applied = base;
  try {
    ph::ApplyConfigJson(file.value, applied);
  } catch (const std::exception& e) {
    CheckReason("configuration", e.what(), text);
    return;
  }
  const json printed = ph::ConfigToJson(applied);
  pc::BoardConfig again = base;
  ph::ApplyConfigJson(printed, again);
  if (ph::ConfigToJson(again) != printed)
    Fail("a configuration changes when printed and read back", printed.dump());
  pc::ConfigError config_error;
  (void)pc::ValidateConfig(applied, &config_error);
}

const char kSimRigText[] =
#include "sim_rig_json.inc"
    ;

/// A rig file: refused with the field named, or accepted.
void CheckRig(const std::string& text) {
  const auto rig = cal::ParseRigDescription(text);
  if (!rig.ok()) CheckReason("rig file", rig.message, text);
}

const std::string& ValidJournalText() {
  static const std::string text =
      json{{"rig_time_s", 12.5},
           {"corrections", {{"0", {{0, 0, 0}, {50000, 50600, 49500}}}}},
           {"sweep", {{0, 0}, {10000, 300}}},
           {"map",
            {{"grid_done", 1},
             {"presses", {{0, 0, 0.1, 0.2, 1.1, 0.3, 0.99, 0.01, 0.002, 120, 1.5}}}}}}
          .dump(1);
  return text;
}

/// A journal: refused with the field named, or accepted.
void CheckJournal(const std::string& text) {
  const auto journal = cal::ParseJournal(text);
  if (!journal.ok()) CheckReason("journal", journal.message, text);
}

void CheckPackage(const std::vector<uint8_t>& bytes) {
  const auto package = ph::ReadPackage(bytes);
  if (!package.ok()) {
    if (package.message.empty() || package.status != pp::Status::kImageInvalid)
      Fail("a refused package came without a reason", std::to_string(bytes.size()));
    return;
  }
  const auto again = ph::ReadPackage(ph::WritePackage(package.value));
  if (!again.ok()) Fail("an accepted package does not read back once written", again.message);
  if (again.value.slot_image != package.value.slot_image)
    Fail("a package changes in a round trip", "");
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
      spec.signer = &palpa::testing::DevelopmentSigner();
      p.slot_image[slot] = ph::BuildImage(spec);
    }
    return ph::WritePackage(p);
  }();
  return bytes;
}

/// One number in JSON text (outside strings) replaced by a literal no double holds, no integer
/// fits, or that is otherwise at an edge.
void ReplaceNumber(Bytes& in, std::string& text) {
  static const char* const kLiterals[] = {"1e400",
                                          "-1e999",
                                          "1e-400",
                                          "99999999999999999999",
                                          "-99999999999999999999",
                                          "18446744073709551616",
                                          "-0",
                                          "4294967296",
                                          "2147483648",
                                          "1.7976931348623157e308"};
  std::vector<std::pair<size_t, size_t>> numbers;  // start, length
  bool in_string = false;
  for (size_t i = 0; i < text.size(); ++i) {
    const char ch = text[i];
    if (in_string) {
      if (ch == '\\') ++i;
      if (ch == '"') in_string = false;
      continue;
    }
    if (ch == '"') {
      in_string = true;
    } else if (ch == '-' || (ch >= '0' && ch <= '9')) {
      size_t end = i + 1;
      while (end < text.size() && std::strchr("0123456789.eE+-", text[end]) != nullptr) ++end;
      numbers.push_back({i, end - i});
      i = end - 1;
    }
  }
  if (numbers.empty()) return;
  const auto [at, length] = numbers[in.Word() % numbers.size()];
  text.replace(at, length, kLiterals[in.Byte() % (sizeof(kLiterals) / sizeof(kLiterals[0]))]);
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

/// The reference text of a JSON kind changed as `variant` says (see the top of this file).
std::string Changed(Bytes& in, int variant, const std::string& valid) {
  switch (variant) {
    case 0:
      return in.Rest();
    case 1: {
      json j = json::parse(valid);
      EditOneLeaf(in, j);
      // Invalid UTF-8 in a string value becomes U+FFFD (raw bytes reach the parser in variant 0).
      return j.dump(-1, ' ', false, json::error_handler_t::replace);
    }
    case 2: {
      std::string text = valid;
      ReplaceNumber(in, text);
      return text;
    }
    default: {
      std::string text = valid;
      Damage(in, text);
      return text;
    }
  }
}

/// A stimulus set: refused with a reason, or accepted with every stimulus inside its levels and
/// fingers and following the tumour rule it states.
void CheckStimulusSet(const std::string& text) {
  const auto parsed = ph::ParseStimulusSet(text);
  if (!parsed.ok()) {
    CheckReason("stimulus set", parsed.message, text);
    return;
  }
  const ph::StimulusSet* set = &parsed.value;
  for (const ph::Stimulus& s : set->stimuli) {
    if (s.levels.size() != static_cast<size_t>(set->fingers))
      Fail("an accepted stimulus has the wrong finger count", set->name);
    for (int l : s.levels) {
      if (l < 0 || static_cast<size_t>(l) >= set->levels.size())
        Fail("an accepted stimulus names no level", set->name);
    }
    const auto rule = ph::TumourFingers(s.levels);
    if (!rule || *rule != s.tumour) Fail("an accepted stimulus breaks the rule", set->name);
  }
}

/// A shipped stimulus set's text, picked by the input.
std::string ShippedStimulusSet(Bytes& in) {
  const auto names = ph::ShippedStimulusSets();
  const std::string name = names[in.Byte() % names.size()];
  if (const auto set = ph::LoadStimulusSet(name); !set.ok())
    Fail("a shipped stimulus set does not load", set.message);
  return ph::ShippedStimulusSetText(name);
}

}  // namespace

namespace palpa::testing::files_fuzz {

std::string ChangedJson(Bytes& in, int variant, const std::string& valid) {
  return Changed(in, variant, valid);
}

std::string Damaged(Bytes& in, std::string text) {
  Damage(in, text);
  return text;
}

}  // namespace palpa::testing::files_fuzz

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  Bytes in(data, size);
  const uint8_t mode = in.Byte();
  const int variant = mode / 7 % 4;
  switch (mode % 7) {
    case 0:
      CheckCalibration(Changed(in, variant, SomeValidCalibrationText(in.Byte())));
      break;
    case 1: {
      const pc::BoardConfig& base = *pc::kBoardConfigs[in.Byte() % pc::kBoardConfigCount].config;
      CheckConfigText(base, Changed(in, variant, ph::ConfigToJson(base).dump(1)));
      break;
    }
    case 2:
      CheckRig(Changed(in, variant, kSimRigText));
      break;
    case 3:
      CheckJournal(Changed(in, variant, ValidJournalText()));
      break;
    case 4: {
      const std::string shipped = ShippedStimulusSet(in);
      CheckStimulusSet(Changed(in, variant, shipped));
      break;
    }
    case 5:
      CheckSceneKind(in, variant);
      break;
    default: {
      std::vector<uint8_t> bytes;
      if (variant == 0) {
        const std::string rest = in.Rest();
        bytes.assign(rest.begin(), rest.end());
      } else {
        bytes = ValidPackage();
        Damage(in, bytes);
      }
      CheckPackage(bytes);
      break;
    }
  }
  return 0;
}
