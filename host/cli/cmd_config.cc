// palpa config show|set|load|save|factory-reset: read, change and persist the configuration.
// Changes are checked locally with the firmware's own validation, then sent staged (atomic).
#include <cmath>
#include <cstdio>

#include "cli.h"
#include "palpa/host/config_json.h"
#include "palpa/host/json_check.h"
#include "palpa/host/json_fields.h"

namespace palpa::cli {
namespace {

namespace pp = palpa::protocol;
using nlohmann::json;

/// Sends `config` staged so it applies at once, once the library has checked it as the board
/// would (a configuration it refuses is a usage error: nothing was sent).
int Upload(Context& c, host::Device& d, const host::BoardConfig& config,
           const nlohmann::ordered_json& changes) {
  std::vector<uint8_t> records;
  if (const host::Outcome o = d.EncodeConfig(config, &records); !o.ok())
    return Fail("config", o.status, o.message, kExitUsage);
  const host::Outcome applied = d.ConfigureStaged(records.data(), records.size());
  if (!applied.ok()) return Report(c, applied, "config");
  if (c.json) {
    PrintJson({{"applied", changes}, {"saved", false}});
  } else {
    std::printf("applied (not yet saved: 'palpa config save' keeps it across resets)\n");
  }
  return kExitOk;
}

/// "board.FIELD=V", "lineN.FIELD=V", "fingerN.FIELD=V" (N from 1) applied onto `config`;
/// an invalid argument naming the argument (once) and, for a field that does not exist, the
/// fields there are.
host::Outcome SetFromArgument(const std::string& arg, host::BoardConfig& config,
                              nlohmann::ordered_json& changes) {
  auto invalid = [](std::string why) {
    return host::Outcome::Fail(pp::Status::kInvalidArgument, std::move(why));
  };
  const size_t eq = arg.find('='), dot = arg.find('.');
  if (eq == std::string::npos || dot == std::string::npos || dot > eq) {
    return invalid("'" + arg +
                   "': expected SECTION.FIELD=VALUE, e.g. board.host_timeout_us=200000 or "
                   "line2.slew_pa_per_s=100000");
  }
  const std::string section = arg.substr(0, dot), field = arg.substr(dot + 1, eq - dot - 1),
                    text = arg.substr(eq + 1);
  json value;
  double number = 0;
  if (ParseNumber(text, number)) {
    value = number == static_cast<double>(static_cast<int64_t>(number))
                ? json(static_cast<int64_t>(number))
                : json(number);
  } else if (text == "true" || text == "false") {
    value = text == "true";
  } else if (text == "none" && field == "line_b") {
    value = nullptr;  // no second line, as palpa info says it
  } else {
    value = text;
  }
  auto index_of = [&](const std::string& prefix, uint8_t count, uint8_t& index) {
    double n = 0;
    if (!ParseNumber(section.substr(prefix.size()), n) || n != std::floor(n) || n < 1)
      return invalid("'" + arg + "': expected " + prefix + "N with N from 1, e.g. " + prefix + "2");
    if (n > count)
      return invalid("'" + arg + "': this board has " + prefix + "s 1 to " + std::to_string(count));
    index = static_cast<uint8_t>(n - 1);
    return host::Outcome{};
  };
  pp::ConfigSection kind = pp::ConfigSection::kBoard;
  uint8_t index = 0;
  if (section == "board") {
  } else if (section.rfind("line", 0) == 0) {
    kind = pp::ConfigSection::kLine;
    if (host::Outcome o = index_of("line", config.line_count, index); !o.ok()) return o;
  } else if (section.rfind("finger", 0) == 0) {
    kind = pp::ConfigSection::kFinger;
    if (host::Outcome o = index_of("finger", config.finger_count, index); !o.ok()) return o;
  } else {
    return invalid("'" + arg + "': the section must be board, lineN or fingerN");
  }
  try {
    host::SetConfigField(kind, index, field, value, config);
  } catch (const std::exception& e) {
    return invalid("'" + arg + "': " + e.what());
  }
  changes[section][field] = value;
  return {};
}

}  // namespace

int CmdConfig(Context& c, const std::vector<std::string>& args) {
  if (args.empty()) return Usage("config", "expected show, set, load, save or factory-reset");
  const std::string& what = args[0];
  const std::vector<std::string> rest(args.begin() + 1, args.end());
  json file;
  if (what == "load") {  // the file is read and parsed before anything is sent
    if (rest.size() != 1) return Usage("config", "load takes one FILE");
    auto read = host::ReadJsonFile(rest[0], host::kConfigFileLimits);
    if (!read.ok()) return Usage("config", read.message + " (nothing was sent)");
    file = std::move(read.value);
  } else if (what == "set") {
    if (rest.empty()) return Usage("config", "set takes SECTION.FIELD=VALUE ...");
  } else if (what == "show" || what == "save" || what == "factory-reset") {
    if (!rest.empty()) return Usage("config", what + " takes no arguments");
  } else {
    const std::string near = Suggest(what, {"show", "set", "load", "save", "factory-reset"});
    return Usage("config", "unknown subcommand '" + what + "'" +
                               (near.empty() ? " (expected show, set, load, save, factory-reset)"
                                             : " (did you mean '" + near + "'?)"));
  }
  host::Device* d = c.Device();
  if (d == nullptr) return kExitConnect;
  if (what == "save" || what == "factory-reset") {
    const bool save = what == "save";
    const int rc = Report(c, save ? d->SaveConfig() : d->FactoryReset(), "config " + what);
    if (rc != kExitOk) return rc;
    if (c.json) {
      PrintJson({{save ? "saved" : "factory_reset", true}});
    } else {
      std::printf("%s\n", save ? "saved: the board starts with this configuration from now on"
                               : "back to the factory configuration; nothing saved any more");
    }
    return kExitOk;
  }
  auto read = d->ReadConfig();
  if (!read.ok()) return Fail("config", pp::Status::kIoError, read.message);
  host::BoardConfig& config = read.value;
  if (what == "show") {
    std::printf("%s\n", host::ConfigToJson(config).dump(c.json ? -1 : 2).c_str());
    return kExitOk;
  }
  nlohmann::ordered_json changes = nlohmann::ordered_json::object();
  if (what == "set") {
    for (const std::string& a : rest) {
      if (const host::Outcome o = SetFromArgument(a, config, changes); !o.ok())
        return Usage("config", o.message + " (nothing was sent)");
    }
    return Upload(c, *d, config, changes);
  }
  try {
    host::ApplyConfigJson(file, config);
  } catch (const std::exception& e) {
    return Usage("config", rest[0] + ": " + e.what() + " (nothing was sent)");
  }
  return Upload(c, *d, config, {{"file", rest[0]}});
}

const Command kConfigCommand{
    "config", "config show|set KEY=VALUE...|load FILE|save|factory-reset",
    "show: the live configuration (JSON with --json).\n"
    "set: change fields, e.g. board.host_timeout_us=200000 line2.slew_pa_per_s=100000\n"
    "     finger4.bias_pa=15000 (lines and fingers numbered from 1); checked locally first.\n"
    "load FILE: a JSON file {\"board\":{...},\"lines\":[...],\"fingers\":[...]} (partial "
    "allowed),\n"
    "     validated as a whole and applied atomically.\n"
    "save: persist the live configuration. factory-reset: back to the compiled-in one.",
    CmdConfig};

}  // namespace palpa::cli
