// palpa monitor, palpa record: telemetry live on a terminal, as JSON lines, or to CSV.
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <mutex>
#include <thread>

#include <nlohmann/json.hpp>

#include "cli.h"
#include "palpa/protocol/faults.h"

namespace palpa::cli {
namespace {

namespace pp = palpa::protocol;
std::atomic<bool> g_stop{false};

/// Reads "--rate HZ" and "--duration S" (and the record file) from args.
bool Options(const std::string& command, const std::vector<std::string>& args, double& rate,
             double& duration, std::string* file, int* usage) {
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if ((a == "--rate" || a == "--duration") && i + 1 < args.size()) {
      double v = 0;
      if (!ParseNumber(args[i + 1], v) || v <= 0) {
        *usage = Usage(command, a + " needs a positive number");
        return false;
      }
      (a == "--rate" ? rate : duration) = v;
      ++i;
    } else if (file != nullptr && file->empty() && a[0] != '-') {
      *file = a;
    } else {
      *usage = Usage(command, "unexpected argument '" + a + "'");
      return false;
    }
  }
  return true;
}

}  // namespace

int CmdMonitor(Context& c, const std::vector<std::string>& args) {
  double rate = 10, duration = 0;
  int usage = 0;
  if (!Options("monitor", args, rate, duration, nullptr, &usage)) return usage;
  host::Device* d = c.Device();
  if (d == nullptr) return kExitConnect;
  const pp::HelloReply b = d->info();
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
      nlohmann::json j = {{"board_time_us", at},
                          {"host_time_s", f.host_time_s + tick * t.sample_interval_us / 1e6},
                          {"faults", t.fault_bitmap}};
      for (uint8_t i = 0; i < t.line_count; ++i) {
        const pp::LineSample& s = t.samples[tick * t.line_count + i];
        j["lines"].push_back({{"line", i + 1},
                              {"setpoint_pa", s.setpoint_pa},
                              {"measured_pa", s.measured_pa},
                              {"command_counts", s.command_counts},
                              {"status", s.status}});
      }
      std::printf("%s\n", j.dump().c_str());
    }
    std::fflush(stdout);
  });
  std::signal(SIGINT, [](int) { g_stop = true; });
  const auto start = std::chrono::steady_clock::now();
  while (!g_stop && (duration == 0 || std::chrono::steady_clock::now() - start <
                                          std::chrono::duration<double>(duration))) {
    std::this_thread::sleep_for(std::chrono::duration<double>(1.0 / rate));
    if (c.json) continue;
    std::lock_guard<std::mutex> lock(mutex);
    if (terminal) std::printf("\033[H\033[2J");
    std::printf("%s  %s  faults: 0x%x  frames: %llu\n", d->link().Describe().c_str(),
                b.config_name.data(), latest.fault_bitmap, static_cast<unsigned long long>(frames));
    std::printf("line  kind      setpoint kPa  measured kPa  DAC    status\n");
    for (uint8_t i = 0; i < latest.line_count && i < b.line_count; ++i) {
      const pp::LineSample& s = latest.samples[(latest.tick_count - 1) * latest.line_count + i];
      std::printf("%4u  %-8s  %12.2f  %12.2f  %5u  %s%s%s\n", i + 1,
                  pp::kLineKindNames[static_cast<int>(b.lines[i].kind)], s.setpoint_pa / 1000.0,
                  s.measured_pa / 1000.0, s.command_counts,
                  (s.status & pp::line_status::kSafe) ? "safe " : "",
                  (s.status & pp::line_status::kRaw) ? "raw " : "",
                  (s.status & pp::line_status::kSaturated) ? "saturated" : "");
    }
    std::fflush(stdout);
  }
  d->Unsubscribe(id);
  return kExitOk;
}

int CmdRecord(Context& c, const std::vector<std::string>& args) {
  double rate = 1, duration = 0;
  std::string file;
  int usage = 0;
  if (!Options("record", args, rate, duration, &file, &usage)) return usage;
  if (file.empty()) return Usage("record", "expected FILE.csv");
  if (duration <= 0) return Usage("record", "expected --duration SECONDS");
  host::Device* d = c.Device();
  if (d == nullptr) return kExitConnect;
  const int started = Report(c, d->StartRecording(file), "record");
  if (started != kExitOk) return started;
  std::signal(SIGINT, [](int) { g_stop = true; });
  const auto start = std::chrono::steady_clock::now();
  while (!g_stop &&
         std::chrono::steady_clock::now() - start < std::chrono::duration<double>(duration)) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  const int rc = Report(c, d->StopRecording(), "record");
  if (rc == kExitOk && !c.json) std::printf("recorded %.1f s to %s\n", duration, file.c_str());
  return rc;
}

}  // namespace palpa::cli
