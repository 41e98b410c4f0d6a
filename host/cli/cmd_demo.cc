// palpa demo: a simulated thesis-5finger board plays the thesis's discrimination stimuli; each
// step prints target against achieved (the simulator's truth), settling time and latency.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <mutex>
#include <thread>

#include <nlohmann/json.hpp>

#include "cli.h"
#include "demo_stimuli.h"
#include "palpa/host/file_write.h"
#include "palpa/host/svg_chart.h"

namespace palpa::cli {
namespace {

namespace pp = palpa::protocol;

/// Reads the simulator's truth channel (JSON lines) on its own thread.
class TruthReader {
 public:
  struct Sample {
    double t_s;
    std::vector<double> outputs;  ///< per finger: mm (pneumatic) or N/mm (jamming)
  };
  bool Connect(const std::string& address) {
    const size_t colon = address.rfind(':');
    fd_ = socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(static_cast<uint16_t>(std::stoi(address.substr(colon + 1))));
    inet_pton(AF_INET, address.substr(4, colon - 4).c_str(), &a.sin_addr);
    if (connect(fd_, reinterpret_cast<sockaddr*>(&a), sizeof(a)) != 0) return false;
    thread_ = std::thread([this] { Run(); });
    return true;
  }
  ~TruthReader() {
    stop_ = true;
    if (thread_.joinable()) thread_.join();
    if (fd_ >= 0) close(fd_);
  }
  std::vector<Sample> Since(double t_s) {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<Sample> out;
    for (const Sample& s : samples_) {
      if (s.t_s >= t_s) out.push_back(s);
    }
    return out;
  }
  std::vector<Sample> All() { return Since(-1); }
  double now_s() {
    std::lock_guard<std::mutex> lock(mutex_);
    return samples_.empty() ? 0 : samples_.back().t_s;
  }

 private:
  void Run() {
    std::string pending;
    char buffer[8192];
    while (!stop_) {
      pollfd p{fd_, POLLIN, 0};
      if (poll(&p, 1, 50) <= 0) continue;
      const ssize_t n = read(fd_, buffer, sizeof(buffer));
      if (n <= 0) return;
      pending.append(buffer, static_cast<size_t>(n));
      size_t newline;
      while ((newline = pending.find('\n')) != std::string::npos) {
        const auto j = nlohmann::json::parse(pending.substr(0, newline), nullptr, false);
        pending.erase(0, newline + 1);
        if (j.is_discarded()) continue;
        Sample s{j["board_time_us"].get<double>() / 1e6, {}};
        for (const auto& f : j["fingers"]) {
          s.outputs.push_back(f.contains("deformation_mm") ? f["deformation_mm"].get<double>()
                                                           : f["stiffness_n_per_mm"].get<double>());
        }
        std::lock_guard<std::mutex> lock(mutex_);
        samples_.push_back(s);
      }
    }
  }
  int fd_ = -1;
  std::atomic<bool> stop_{false};
  std::thread thread_;
  std::mutex mutex_;
  std::vector<Sample> samples_;
};

std::string Levels(const std::vector<int>& c) {
  std::string s;
  for (int l : c) s += "L" + std::to_string(l) + " ";
  return s;
}

}  // namespace

int CmdDemo(Context& c, const std::vector<std::string>& args) {
  (void)c;  // the demo always runs on a simulator of its own, whatever --device says
  std::string out = "palpa-demo.svg";
  double speed = 4;
  for (size_t i = 0; i < args.size(); ++i) {
    const bool has_value = i + 1 < args.size();
    if (args[i] == "--out") {
      if (!has_value) return Usage("demo", "--out needs a file name for the chart");
      out = args[++i];
    } else if (args[i] == "--speed") {
      if (!has_value || !ParseNumber(args[++i], speed) || speed < 0.1 || speed > 20)
        return Usage("demo", "--speed needs a number from 0.1 to 20");
    } else {
      return Usage("demo", "unexpected argument '" + args[i] + "'");
    }
  }
  // Checked before the run, not after it: the chart is written at the end.
  const std::filesystem::path chart_dir = std::filesystem::path(out).parent_path();
  const std::string dir = chart_dir.empty() ? "." : chart_dir.string();
  if (!std::filesystem::is_directory(dir) || access(dir.c_str(), W_OK) != 0) {
    return Usage("demo",
                 "--out " + out + ": " + dir + " is not a directory this user can write to");
  }
  char speed_text[16];
  std::snprintf(speed_text, sizeof(speed_text), "%g", speed);
  std::printf(
      "palpa demo: starting a simulated thesis-5finger board (plant level 3: regulators with "
      "static errors,\n"
      "hysteretic fingers, real sensors), running %sx faster than real time\n",
      speed_text);
  std::string truth_address, error;
  auto transport = host::LaunchSim(
      "thesis-5finger", {"--plant", "3", "--speed", speed_text, "--truth-every-ms", "10"},
      &truth_address, &error);
  if (!transport.ok()) {
    std::fprintf(stderr, "palpa demo: %s\n", error.c_str());
    return kExitConnect;
  }
  auto device = host::Device::Attach(std::move(transport.value), host::DeviceOptions{}, &error);
  if (!device.ok()) {
    std::fprintf(stderr, "palpa demo: %s\n", error.c_str());
    return kExitConnect;
  }
  host::Device& d = *device.value;
  TruthReader truth;
  if (!truth.Connect(truth_address)) {
    std::fprintf(stderr, "palpa demo: cannot read the simulator's truth channel at %s\n",
                 truth_address.c_str());
    return kExitConnect;
  }
  const pp::HelloReply board = d.info();
  const host::LevelTables levels = host::LevelTables::Shipped();

  struct Step {
    std::vector<int> levels;
    bool jamming;
  };
  std::vector<Step> steps;
  for (const auto& combo : TumourCombinations(3, 3)) steps.push_back({combo, false});
  for (const auto& combo : TumourCombinations(2, 3)) steps.push_back({combo, true});
  std::printf(
      "stimuli: %zu three-finger pneumatic combinations of 0/10/30 kPa, %zu two-finger jamming "
      "combinations\n"
      "of 0/-10/-100 kPa at 20 kPa bias (a tumour: one finger or two adjacent fingers stiffer than "
      "the rest)\n\n",
      steps.size() - 9, size_t{9});
  std::printf(
      "  step  fingers      target                         achieved (true)                settled  "
      " latency\n");
  host::Chart chart;
  chart.title = "palpa demo: thesis stimuli on a simulated thesis-5finger board (true outputs)";
  chart.x_label = "board time (s)";
  chart.y_label = "deformation (mm), fingers 1-3 / stiffness (N/mm), fingers 4-5";
  std::vector<host::Series> targets(5);
  double worst_error_pct = 0;
  for (size_t n = 0; n < steps.size(); ++n) {
    const Step& s = steps[n];
    std::vector<host::FingerRequest> requests;
    std::vector<double> want(5, 0);
    for (size_t i = 0; i < s.levels.size(); ++i) {
      const uint8_t finger = static_cast<uint8_t>(s.jamming ? 3 + i : i);
      requests.push_back({finger, {host::TargetKind::kLevel, static_cast<double>(s.levels[i])}});
      const host::Mapped m =
          host::MapRequest(board.fingers[finger], levels, d.curves(finger),
                           {host::TargetKind::kLevel, static_cast<double>(s.levels[i])});
      want[finger] = s.jamming ? (m.target == 0 ? 0.7 : m.target / 1000.0) : m.target / 1000.0;
    }
    const double t0 = truth.now_s();
    const auto sent = std::chrono::steady_clock::now();
    const host::Outcome o = d.Set(requests);
    const double latency_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - sent).count();
    if (!o.ok()) {
      std::fprintf(stderr, "palpa demo: step %zu: %s\n", n + 1, o.message.c_str());
      return kExitFailed;
    }
    const double hold_s = s.jamming ? 3.5 : 1.6;  // board time: vacuum chambers are slow
    while (truth.now_s() < t0 + hold_s) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    const auto trace = truth.Since(t0);
    const std::vector<double>& achieved = trace.back().outputs;
    // Settled: from when every driven finger stays within 5 % (0.03 mm near zero) of where it ends.
    double settled_s = 0;
    for (const auto& sample : trace) {
      for (const auto& r : requests) {
        const double band = std::max(0.05 * std::fabs(achieved[r.finger]), s.jamming ? 0.01 : 0.03);
        if (std::fabs(sample.outputs[r.finger] - achieved[r.finger]) > band)
          settled_s = sample.t_s - t0;
      }
    }
    std::string target_text, achieved_text;
    char cell[32];
    for (const auto& r : requests) {
      std::snprintf(cell, sizeof(cell), "%5.2f ", want[r.finger]);
      target_text += cell;
      std::snprintf(cell, sizeof(cell), "%5.2f ", achieved[r.finger]);
      achieved_text += cell;
      if (want[r.finger] > 0.1)
        worst_error_pct = std::max(
            worst_error_pct, 100 * std::fabs(achieved[r.finger] - want[r.finger]) / want[r.finger]);
      targets[r.finger].points.push_back({t0, want[r.finger]});
      targets[r.finger].points.push_back({t0 + hold_s, want[r.finger]});
    }
    std::printf("  %2zu/%zu  %-12s %-4s %-25s %-4s %-25s %5.2f s  %5.1f ms\n", n + 1, steps.size(),
                Levels(s.levels).c_str(), s.jamming ? "N/mm" : "mm", target_text.c_str(),
                s.jamming ? "N/mm" : "mm", achieved_text.c_str(), settled_s, latency_ms);
    std::fflush(stdout);
  }
  const auto all = truth.All();
  const char* names[] = {"finger 1 (mm)", "finger 2 (mm)", "finger 3 (mm)", "finger 4 (N/mm)",
                         "finger 5 (N/mm)"};
  for (size_t f = 0; f < 5; ++f) {
    host::Series trace{names[f], {}, "", false, false};
    for (size_t i = 0; i < all.size(); i += 5)
      trace.points.push_back({all[i].t_s, all[i].outputs[f]});
    chart.series.push_back(trace);
  }
  chart.width = 1100;
  d.EStop();
  if (!host::WriteFileWhole(out, host::RenderSvg(chart), &error)) {
    std::fprintf(stderr, "palpa demo: %s\n", error.c_str());
    return kExitFailed;
  }
  std::printf(
      "\nlargest difference between a target and the true output: %.1f %% — the nominal static "
      "inverse\n"
      "with no hysteresis compensation (the unit's own curves and the film's loop show through).\n",
      worst_error_pct);
  std::printf("traces plotted to %s\n", out.c_str());
  return kExitOk;
}

}  // namespace palpa::cli
