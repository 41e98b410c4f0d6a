// palpa list, info, diag, estop, clear.
#include <algorithm>
#include <cstdio>

#include <nlohmann/json.hpp>

#include "cli.h"
#include "palpa/host/bit_names.h"
#include "palpa/host/board_json.h"
#include "palpa/host/device_list.h"
#include "palpa/host/fault_text.h"
#include "palpa/host/field_text.h"
#include "palpa/protocol/faults.h"
#include "sim_state.h"

namespace palpa::cli {
namespace {

namespace pp = palpa::protocol;
using nlohmann::ordered_json;

}  // namespace

int CmdList(Context& c, const std::vector<std::string>& args) {
  if (!args.empty()) return Usage("list", "takes no arguments");
  const std::vector<host::FoundDevice> found = host::ListDevices();
  const auto sim = FindRunningSim();
  if (c.json) {
    ordered_json serial = ordered_json::array(), hid = ordered_json::array(),
                 usb = ordered_json::array(), devices = ordered_json::array();
    for (const auto& d : found) {
      if (d.uri.rfind("serial:", 0) == 0) serial.push_back(d.uri);
      if (d.palpa && d.uri.rfind("hid:", 0) == 0) hid.push_back(d.uri);
      if (d.palpa && d.uri.rfind("usb:", 0) == 0) usb.push_back(d.uri);
      devices.push_back({{"uri", d.uri},
                         {"product", d.product},
                         {"serial_number", d.serial_number},
                         {"palpa", d.palpa},
                         {"note", d.note}});
    }
    PrintJson({{"serial", serial},
               {"hid", hid},
               {"usb", usb},
               {"devices", devices},
               {"sim", sim ? ordered_json{{"device", sim->uri}, {"config", sim->config}}
                           : ordered_json(nullptr)}});
    return kExitOk;
  }
  auto line = [](const host::FoundDevice& d) {
    const std::string what =
        d.palpa ? "palpa board: " + d.product +
                      (d.serial_number.empty() ? "" : ", serial " + d.serial_number)
        : d.product.empty() ? d.note
                            : d.product + " (" + d.note + ")";
    std::printf("  %-28s %s\n", d.uri.c_str(), what.c_str());
  };
  auto section = [&](const char* title, auto wanted) {
    const auto n = std::count_if(found.begin(), found.end(), wanted);
    std::printf("%s:%s\n", title, n == 0 ? " none" : "");
    for (const auto& d : found)
      if (wanted(d)) line(d);
  };
  auto scheme = [](const host::FoundDevice& d, const char* s) { return d.uri.rfind(s, 0) == 0; };
  section("serial ports", [&](const host::FoundDevice& d) { return scheme(d, "serial:"); });
  section("palpa boards on HID (usb 1209:0001, product \"palpa…\")",
          [&](const host::FoundDevice& d) { return d.palpa && scheme(d, "hid:"); });
  section("palpa boards on vendor bulk (usb 1209:0001, product \"palpa…\")",
          [&](const host::FoundDevice& d) { return d.palpa && scheme(d, "usb:"); });
  for (const auto& d : found) {
    if (!d.palpa && !scheme(d, "serial:"))
      std::printf("ignored: %s, %s\n", d.uri.c_str(), d.note.c_str());
  }
  if (sim) {
    std::printf("simulated board (palpa sim start): %s, %s\n", sim->uri.c_str(),
                sim->config.c_str());
  } else {
    std::printf("(a simulated board is always there: 'palpa sim start' keeps one running)\n");
  }
  return kExitOk;
}

namespace {}  // namespace

int CmdInfo(Context& c, const std::vector<std::string>& args) {
  if (!args.empty()) return Usage("info", "takes no arguments");
  host::Device* d = c.Device();
  if (d == nullptr) return kExitConnect;
  const pp::HelloReply b = d->info();
  const auto diag = d->Diagnostics();  // the configuration's state now, not at Hello
  if (!diag.ok()) return Fail("info", diag.status, diag.message);
  const std::string state = host::ConfigStateText(diag.value);
  const std::string firmware = std::to_string(b.firmware_major) + "." +
                               std::to_string(b.firmware_minor) + "." +
                               std::to_string(b.firmware_patch);
  const std::string name = host::FieldText(b.config_name);
  if (c.json) {
    ordered_json j;
    j["device"] = d->link().Describe();
    j["simulator"] = c.throwaway ? "throwaway" : (b.plant_simulated ? "kept" : "none");
    j["board"] = host::BoardIdentityJson(b, diag.value, d->link().catalog_matches());
    j["lines"] = host::LinesJson(b);
    j["fingers"] = host::FingersJson(b);
    j["numbering"] = "lines and fingers from 1";
    PrintJson(j);
    return kExitOk;
  }
  std::printf("device        %s\n", d->link().Describe().c_str());
  std::printf("board         %s, id %u%s\n", pp::kBoardKindNames[static_cast<int>(b.board_kind)],
              b.board_id, b.plant_simulated ? " (simulated plant)" : "");
  std::printf("firmware      %s, protocol %u, catalog 0x%08x%s\n", firmware.c_str(),
              b.protocol_version, b.catalog_hash,
              d->link().catalog_matches() ? "" : " (differs from this host's)");
  std::printf("image slot    %u, anti-rollback counter %u\n", b.active_slot, b.rollback_counter);
  std::printf("configuration %s (%s)\n", name.c_str(), state.c_str());
  std::printf("reset cause   %s; faults: %s\n",
              pp::kResetCauseNames[static_cast<int>(b.reset_cause)],
              host::FaultNames(diag.value.fault_bitmap).c_str());
  if (b.time_scale != 1.0f) std::printf("time scale    %gx\n", static_cast<double>(b.time_scale));
  for (uint8_t i = 0; i < b.line_count; ++i) {
    std::printf("line %u        %-8s %7.1f … %6.1f kPa%s\n", i + 1,
                pp::kLineKindNames[static_cast<int>(b.lines[i].kind)],
                b.lines[i].limit_min_pa / 1000.0, b.lines[i].limit_max_pa / 1000.0,
                b.lines[i].has_sensor ? ", sensor" : "");
  }
  for (uint8_t f = 0; f < b.finger_count; ++f) {
    const bool jamming = b.fingers[f].kind == pp::FingerKind::kJamming;
    const std::string second =
        b.fingers[f].line_b == pp::kNoLine ? "none" : std::to_string(b.fingers[f].line_b + 1);
    std::printf("finger %u      %-9s line %u, second line %s  (%s)\n", f + 1,
                jamming ? "jamming" : "pneumatic", b.fingers[f].line_a + 1, second.c_str(),
                jamming ? "N/mm, levels, 0..1, kPa" : "mm, levels, 0..1, kPa");
  }
  return kExitOk;
}

int CmdDiag(Context& c, const std::vector<std::string>& args) {
  if (!args.empty()) return Usage("diag", "takes no arguments");
  host::Device* d = c.Device();
  if (d == nullptr) return kExitConnect;
  const auto diag = d->Diagnostics();
  const auto stats = d->LoopStats();
  if (!diag.ok()) return Fail("diag", diag.status, diag.message);
  if (!stats.ok()) return Fail("diag", stats.status, stats.message);
  const host::LinkCounters link = d->link().counters();
  if (c.json) {
    PrintJson(host::DiagnosticsJson(diag.value, stats.value, link, 1));
    return kExitOk;
  }
  std::printf("reset cause     %s (boot %u), up %.1f s\n",
              pp::kResetCauseNames[static_cast<int>(diag.value.reset_cause)], diag.value.boot_count,
              static_cast<double>(diag.value.uptime_us) / 1e6);
  std::printf("faults latched  %s\n", host::FaultNames(diag.value.fault_bitmap).c_str());
  std::printf("faults active   %s\n", host::FaultNames(diag.value.active_conditions).c_str());
  const std::vector<int> fell_back = host::ShapingFellBackLines(diag.value, 1);
  if (!fell_back.empty()) {
    std::string lines;
    for (int line : fell_back) lines += " " + std::to_string(line);
    std::printf("shaped steps    fell back to unshaped on line%s%s (recalibrate the chamber)\n",
                fell_back.size() > 1 ? "s" : "", lines.c_str());
  }
  for (uint8_t i = 0; i < diag.value.history_count; ++i) {
    const auto& h = diag.value.history[i];
    std::printf("  %10.3f s  %-20s %s\n", static_cast<double>(h.time_us) / 1e6,
                host::FaultName(h.fault).c_str(), host::FaultDetail(h.fault, h.detail, 1).c_str());
  }
  const auto& s = stats.value;
  std::printf(
      "loop            %llu ticks of %u us; worst %u us, mean %u us, jitter %u us, %u overruns\n",
      static_cast<unsigned long long>(s.ticks), s.period_us, s.worst_tick_us, s.mean_tick_us,
      s.jitter_max_us, s.overruns);
  std::printf(
      "link            board: %u frames in, %u errors, %u telemetry frames dropped; host: %llu "
      "retransmissions\n",
      s.rx_frames, s.rx_errors, s.telemetry_dropped,
      static_cast<unsigned long long>(link.retransmissions));
  return kExitOk;
}

int CmdEStop(Context& c, const std::vector<std::string>& args) {
  if (!args.empty()) return Usage("estop", "takes no arguments");
  host::Device* d = c.Device();
  if (d == nullptr) return kExitConnect;
  const int rc = Report(c, d->EStop(), "estop");
  if (rc != kExitOk) return rc;
  if (c.json) {
    PrintJson({{"estop", "acknowledged"},
               {"faults", host::FaultList(pp::FaultBit(pp::Fault::kEStopCommand))}});
  } else {
    std::printf("EStop acknowledged: every line is safe until 'palpa clear' and new setpoints\n");
  }
  return rc;
}

int CmdClear(Context& c, const std::vector<std::string>& args) {
  if (!args.empty()) return Usage("clear", "takes no arguments");
  host::Device* d = c.Device();
  if (d == nullptr) return kExitConnect;
  const auto before = d->Diagnostics();
  if (!before.ok()) return Fail("clear", before.status, before.message);
  const int rc = Report(c, d->ClearFault(), "clear");
  if (rc != kExitOk) return rc;
  const std::vector<std::string> cleared = host::FaultList(before.value.fault_bitmap);
  if (c.json) {
    PrintJson({{"cleared", cleared}});
  } else if (cleared.empty()) {
    std::printf("no faults were latched; outputs stay as they were\n");
  } else {
    std::printf("faults cleared: %s; outputs stay safe until new setpoints arrive\n",
                host::JoinNames(cleared, ", ", "none").c_str());
  }
  return rc;
}

const Command kListCommand{"list", "list",
                           "Serial ports, and HID and USB devices with palpa's USB id (1209:0001).",
                           CmdList};

const Command kInfoCommand{
    "info", "info", "The board: kind, id, firmware, catalog, configuration, lines and fingers.",
    CmdInfo};

const Command kDiagCommand{
    "diag", "diag", "Reset cause, latched and active faults, fault history, loop statistics.",
    CmdDiag};

const Command kEStopCommand{"estop", "estop",
                            "Every line to its safe value now, latched until cleared.", CmdEStop};

const Command kClearCommand{
    "clear", "clear",
    "Clear latched faults whose cause is gone; outputs stay safe until new setpoints.", CmdClear};

}  // namespace palpa::cli
