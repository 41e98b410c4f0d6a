// palpa monitor, palpa record: telemetry live on a terminal, as JSON lines, or to CSV.
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <mutex>
#include <string>
#include <thread>

#include "cli.h"
#include "palpa/host/bit_names.h"
#include "palpa/host/field_text.h"
#include "palpa/protocol/faults.h"

namespace palpa::cli {
namespace {

namespace pp = palpa::protocol;

struct TelemetryOptions {
  double rate = 0;  ///< 0: not given
  double duration = 0;
  std::string file;
  bool long_layout = false;
};

/// Reads "--rate HZ", "--duration S" (and for record the file and --long) from args.
bool Options(const std::string& command, const std::vector<std::string>& args, TelemetryOptions& o,
             bool record, int* usage) {
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a == "--rate" || a == "--duration") {
      const host::Result<std::string> option = OptionValue(args, i);
      if (!option.ok()) {
        *usage = Usage(command, option.message + " (" + a + (a == "--rate" ? " HZ)" : " SECONDS)"));
        return false;
      }
      const std::string& value = option.value;
      double v = 0;
      if (!ParseNumber(value, v) || v <= 0) {
        *usage = Usage(command, a + " " + value + ": a positive number");
        return false;
      }
      (a == "--rate" ? o.rate : o.duration) = v;
      ++i;
    } else if (record && a == "--long") {
      o.long_layout = true;
    } else if (record && o.file.empty() && a[0] != '-') {
      o.file = a;
    } else {
      *usage = Usage(command, "unexpected argument '" + a + "'");
      return false;
    }
  }
  return true;
}

/// Samples per second the board sends: one every telemetry_decimation ticks of its loop.
host::Result<double> BoardRate(host::Device& d) {
  const auto board = d.ReadBoard();
  if (!board.ok()) return board.outcome();
  const auto stats = d.LoopStats();
  if (!stats.ok()) return stats.outcome();
  const double period_us = stats.value.period_us > 0 ? stats.value.period_us : 1000;
  return 1e6 / (period_us * std::max<uint16_t>(board.value.telemetry_decimation, 1));
}

nlohmann::ordered_json SampleJson(const pp::HelloReply& b, const pp::Telemetry& t, uint8_t tick,
                                  double host_time_s,
                                  const std::vector<host::FingerCurves>& curves) {
  const uint64_t at = t.first_sample_us + static_cast<uint64_t>(tick) * t.sample_interval_us;
  nlohmann::ordered_json j = {{"board_time_us", at},
                              {"host_time_s", host_time_s + tick * t.sample_interval_us / 1e6},
                              {"faults", host::FaultList(t.fault_bitmap)},
                              {"fault_bitmap", t.fault_bitmap}};
  const pp::LineSample* lines = &t.samples[tick * t.line_count];
  for (uint8_t i = 0; i < t.line_count; ++i) {
    j["lines"].push_back({{"line", i + 1},
                          {"setpoint_pa", lines[i].setpoint_pa},
                          {"measured_pa", lines[i].measured_pa},
                          {"command_counts", lines[i].command_counts},
                          {"status", host::LineStatusList(lines[i].status)},
                          {"status_bits", lines[i].status}});
  }
  if (t.line_count == b.line_count) {
    const std::vector<double> outputs = host::EstimateFingerOutputs(b, curves, lines);
    for (uint8_t f = 0; f < outputs.size(); ++f) {
      j["fingers"].push_back({{"finger", f + 1},
                              {"output", outputs[f]},
                              {"unit", host::OutputUnitName(b.fingers[f].kind)}});
    }
  }
  return j;
}

void PrintTable(host::Device& d, const pp::HelloReply& b, const pp::Telemetry& latest,
                uint64_t frames, const std::vector<host::FingerCurves>& curves) {
  std::printf("%s  %s  faults: %s  frames: %llu\n", d.link().Describe().c_str(),
              host::FieldText(b.config_name).c_str(),
              host::JoinNames(host::FaultList(latest.fault_bitmap), ", ", "none").c_str(),
              static_cast<unsigned long long>(frames));
  if (latest.tick_count == 0 || latest.line_count != b.line_count) return;
  const pp::LineSample* lines = &latest.samples[(latest.tick_count - 1) * latest.line_count];
  std::printf("line  kind      setpoint kPa  measured kPa  DAC    status\n");
  for (uint8_t i = 0; i < b.line_count; ++i) {
    std::printf("%4u  %-8s  %12.2f  %12.2f  %5u  %s\n", i + 1,
                pp::kLineKindNames[static_cast<int>(b.lines[i].kind)],
                lines[i].setpoint_pa / 1000.0, lines[i].measured_pa / 1000.0,
                lines[i].command_counts,
                host::JoinNames(host::LineStatusList(lines[i].status), " ", "").c_str());
  }
  const std::vector<double> outputs = host::EstimateFingerOutputs(b, curves, lines);
  std::printf("finger  kind       output  (from the measured pressure through its curve)\n");
  for (uint8_t f = 0; f < outputs.size(); ++f) {
    const bool jamming = b.fingers[f].kind == pp::FingerKind::kJamming;
    std::printf("%6u  %-9s  %6.3f %s\n", f + 1, jamming ? "jamming" : "pneumatic", outputs[f],
                host::OutputUnitName(b.fingers[f].kind));
  }
}

}  // namespace

int CmdMonitor(Context& c, const std::vector<std::string>& args) {
  TelemetryOptions o;
  int usage = 0;
  if (!Options("monitor", args, o, false, &usage)) return usage;
  host::Device* d = c.Device();
  if (d == nullptr) return kExitConnect;
  const host::Result<double> board = BoardRate(*d);
  if (!board.ok()) return Fail("monitor", board.status, board.message);
  const double board_rate = board.value;
  if (o.rate > board_rate) {
    char text[160];
    std::snprintf(text, sizeof(text),
                  "--rate %g: the board sends %g samples a second (its telemetry_decimation); "
                  "ask for %g or less",
                  o.rate, board_rate, board_rate);
    return Usage("monitor", text);
  }
  const double rate = o.rate > 0 ? o.rate : std::min(10.0, board_rate);
  const pp::HelloReply b = d->info();
  std::vector<host::FingerCurves> curves;
  for (uint8_t f = 0; f < b.finger_count; ++f) curves.push_back(d->curves(f));
  WarnCurves(*d);
  const bool terminal = isatty(STDOUT_FILENO) && !c.json;
  std::mutex mutex;
  pp::Telemetry latest{};
  uint64_t frames = 0;
  const uint64_t every_us = static_cast<uint64_t>(1e6 / rate);
  uint64_t next_us = 0;
  const int id = d->Subscribe([&](const host::TelemetryFrame& f) {
    std::lock_guard<std::mutex> lock(mutex);
    latest = f.telemetry;
    ++frames;
    if (!c.json) return;
    const pp::Telemetry& t = f.telemetry;
    for (uint8_t tick = 0; tick < t.tick_count; ++tick) {
      const uint64_t at = t.first_sample_us + static_cast<uint64_t>(tick) * t.sample_interval_us;
      if (at < next_us) continue;
      next_us = at + every_us;
      std::printf("%s\n", SampleJson(b, t, tick, f.host_time_s, curves).dump().c_str());
    }
    std::fflush(stdout);
  });
  const PollsInterruption polls;
  const auto start = std::chrono::steady_clock::now();
  std::string last_event;
  while (!Interrupted() && (o.duration == 0 || std::chrono::steady_clock::now() - start <
                                                   std::chrono::duration<double>(o.duration))) {
    std::this_thread::sleep_for(std::chrono::duration<double>(1.0 / std::min(rate, 10.0)));
    // What happened to the link (a board reset, a cable pulled and plugged back in), on stderr so
    // that JSON lines on stdout stay clean.
    for (const std::string& e : d->link().TakeEvents()) {
      std::fprintf(stderr, "palpa monitor: %s\n", e.c_str());
      last_event = e;
    }
    if (d->link().ended()) {  // e.g. another host holds the board now
      d->Unsubscribe(id);
      std::fprintf(stderr, "palpa monitor: %s\n", d->link().session_end().c_str());
      return kExitFailed;
    }
    if (c.json) continue;
    std::lock_guard<std::mutex> lock(mutex);
    if (terminal) std::printf("\033[H\033[2J");
    PrintTable(*d, b, latest, frames, curves);
    if (terminal && !last_event.empty()) std::printf("last event: %s\n", last_event.c_str());
    std::fflush(stdout);
  }
  d->Unsubscribe(id);
  return kExitOk;
}

int CmdRecord(Context& c, const std::vector<std::string>& args) {
  TelemetryOptions o;
  int usage = 0;
  if (!Options("record", args, o, true, &usage)) return usage;
  if (o.file.empty()) return Usage("record", "expected FILE.csv");
  if (o.duration <= 0) return Usage("record", "expected --duration SECONDS");
  if (o.rate > 0) return Usage("record", "--rate: a recording keeps every sample the board sends");
  host::Device* d = c.Device();
  if (d == nullptr) return kExitConnect;
  const host::RecordLayout layout =
      o.long_layout ? host::RecordLayout::kLong : host::RecordLayout::kWide;
  const int started = Report(c, d->StartRecording(o.file, layout), "record");
  if (started == kExitOk) WarnCurves(*d);
  if (started != kExitOk) return started;
  const PollsInterruption polls;
  const auto start = std::chrono::steady_clock::now();
  while (!Interrupted() &&
         std::chrono::steady_clock::now() - start < std::chrono::duration<double>(o.duration)) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const int rc = Report(c, d->StopRecording(), "record");
  if (rc != kExitOk) return rc;
  if (c.json) {
    PrintJson(
        {{"file", o.file}, {"seconds", seconds}, {"layout", o.long_layout ? "long" : "wide"}});
  } else {
    std::printf(
        "recorded %.1f s to %s (%s)\n", seconds, o.file.c_str(),
        o.long_layout ? "long layout: a row per line per sample" : "wide layout: a row per sample");
  }
  return rc;
}

const Command kMonitorCommand{
    "monitor", "monitor [--rate HZ] [--duration S]",
    "A live table of every line (one JSON object per sample with --json); Ctrl-C ends it.",
    CmdMonitor};

const Command kRecordCommand{
    "record", "record FILE.csv --duration S",
    "Telemetry to CSV; the first line is a JSON header (board, configuration, units, clock).",
    CmdRecord};

}  // namespace palpa::cli
