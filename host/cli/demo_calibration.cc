// The demo's calibration step: the pneumatic fingers calibrated on simulated rigs, in parallel.
#include "demo_calibration.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <functional>
#include <mutex>
#include <thread>

#include "cli.h"
#include "palpa/calibration/board_rig.h"
#include "palpa/calibration/session.h"
#include "palpa/host/field_text.h"

namespace palpa::cli {
namespace {

namespace cal = calibration;
namespace pp = palpa::protocol;

/// Every finger's progress on one line of a terminal (the step table stays on stdout).
class ProgressLine {
 public:
  explicit ProgressLine(const std::vector<int>& fingers)
      : fingers_(fingers), done_(fingers.size(), 0), total_(fingers.size(), 0) {}
  void Report(size_t i, const cal::Progress& p) {
    if (!isatty(STDERR_FILENO)) return;
    std::lock_guard<std::mutex> lock(mutex_);
    done_[i] = p.done;
    total_[i] = p.total;
    std::string line = "\r ";
    for (size_t k = 0; k < done_.size(); ++k) {
      line += " finger " + std::to_string(fingers_[k] + 1) + " " + std::to_string(done_[k]) + "/" +
              std::to_string(total_[k]) + (k + 1 < done_.size() ? "," : "");
    }
    std::fputs(line.c_str(), stderr);
    std::fflush(stderr);
  }
  ~ProgressLine() {
    if (isatty(STDERR_FILENO)) std::fputs("\r\033[K", stderr);  // the line goes with the step
  }

 private:
  std::mutex mutex_;
  std::vector<int> fingers_, done_, total_;
};

/// One finger on its own simulator: the quick protocol, api(8).
host::Result<host::CalibrationFile> CalibrateOne(
    const std::string& config, int finger, double speed,
    const std::function<void(const cal::Progress&)>& progress) {
  const host::SimulatedPlant plant;  // the demo board's: palpa-sim's defaults
  host::Result<cal::BoardRig> opened = cal::OpenSimulatedRig(config, finger, speed, plant, 1);
  if (!opened.ok()) return opened.outcome();
  cal::BoardRig* sim = &opened.value;
  const auto fc = sim->device->ReadFinger(static_cast<uint8_t>(finger));
  if (!fc.ok()) return fc.outcome();
  cal::SessionOptions options;
  options.finger = static_cast<uint8_t>(finger);
  options.protocol = cal::QuickProtocol();
  options.protocol.compensator = protocol::CompensatorKind::kAsymmetricPi;
  options.protocol.compensator_operators = kDemoOperators;
  options.date = "";  // nothing written and nothing to resume: a failed demo is run again
  options.simulation = sim->simulation;
  cal::Session session(sim->rig(), host::FieldText(fc.value.actuator_serial),
                       sim->device->info().board_id, false, options);
  const host::Outcome o = session.Run(progress);
  if (!o.ok()) {  // as palpa calibrate: a model asked for and not fitted fails
    return {o.status, o.status == protocol::Status::kBadValue
                          ? "api(" + std::to_string(kDemoOperators) +
                                ") not fitted: " + session.result().fit.error
                          : o.message};
  }
  return session.result().file;
}

/// `fingers` calibrated in parallel, one file each, in order; the first failure names its finger.
host::Result<std::vector<host::CalibrationFile>> CalibrateSimulatedFingers(
    const std::string& config, const std::vector<int>& fingers, double speed) {
  std::vector<host::Result<host::CalibrationFile>> results(fingers.size(), host::CalibrationFile{});
  {
    ProgressLine line(fingers);
    std::vector<std::thread> threads;
    for (size_t i = 0; i < fingers.size(); ++i) {
      threads.emplace_back([&, i] {
        const auto progress = [&line, i](const cal::Progress& p) { line.Report(i, p); };
        results[i] = CalibrateOne(config, fingers[i], speed, progress);
      });
    }
    for (std::thread& t : threads) t.join();
  }
  std::vector<host::CalibrationFile> files;
  for (size_t i = 0; i < fingers.size(); ++i) {
    if (!results[i].ok()) {
      return {results[i].status,
              "calibrating finger " + std::to_string(fingers[i] + 1) + ": " + results[i].message};
    }
    files.push_back(std::move(results[i].value));
  }
  return files;
}

/// DIR/SERIAL.json of each serial that has one, or why one cannot be read.
host::Result<std::vector<host::CalibrationFile>> LoadCalibrations(
    const std::string& dir, const std::vector<std::string>& serials) {
  std::vector<host::CalibrationFile> files;
  for (const std::string& serial : serials) {
    // The library's lookup also refuses a file whose actuator is another than its name says.
    auto file = host::FindCalibration(dir, serial);
    if (file.status == pp::Status::kNotFound) continue;
    if (!file.ok()) return file.outcome();
    files.push_back(std::move(file.value));
  }
  return files;
}

std::string Serial(host::Device& d, uint8_t finger) {
  const auto f = d.ReadFinger(finger);
  if (!f.ok()) return "";
  return host::FieldText(f.value.actuator_serial);
}

}  // namespace

PneumaticFingers FindPneumatic(host::Device& d) {
  PneumaticFingers p;
  for (uint8_t f = 0; f < d.info().finger_count; ++f) {
    if (d.info().fingers[f].kind != pp::FingerKind::kPneumatic) continue;
    p.fingers.push_back(f);
    p.serials.push_back(Serial(d, f));
  }
  return p;
}

std::optional<std::vector<host::CalibrationFile>> ReadCalibrationDir(const PneumaticFingers& p,
                                                                     const std::string& dir) {
  auto files = LoadCalibrations(dir, p.serials);
  if (files.ok() && files.value.empty()) {
    files.message = "--calibration " + dir + ": no calibration file of " + p.serials.front() +
                    " .. " + p.serials.back() + " (SERIAL.json)";
  }
  if (!files.ok() || files.value.empty()) {
    Fail("demo", protocol::Status::kNotFound, files.message);
    return std::nullopt;
  }
  return std::move(files.value);
}

std::optional<std::vector<host::CalibrationFile>> CalibrateOnSimulatedRigs(
    const std::string& config, const PneumaticFingers& p, double speed) {
  std::fprintf(
      TextOut(),
      "\ncalibrating fingers 1-%zu on simulated rigs of their own, in parallel (palpa calibrate "
      "--rig sim\n--quick --compensator api:%d: a sweep with nested reversals measured by the "
      "rig's stage and force sensor)\n",
      p.fingers.size(), kDemoOperators);
  const auto started = std::chrono::steady_clock::now();
  auto files = CalibrateSimulatedFingers(config, p.fingers, speed);
  if (!files.ok()) {
    Fail("demo", protocol::Status::kUnavailable, files.message);
    return std::nullopt;
  }
  std::fprintf(TextOut(), "  done in %.0f s\n",
               std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count());
  return std::move(files.value);
}

bool ApplyCalibrations(host::Device& d, const PneumaticFingers& p,
                       const std::vector<host::CalibrationFile>& files, std::string* compensator) {
  for (const host::CalibrationFile& file : files) {
    const auto at = std::find(p.serials.begin(), p.serials.end(), file.actuator_serial);
    if (at == p.serials.end()) {
      Fail("demo", protocol::Status::kNotFound,
           "no pneumatic finger carries " + file.actuator_serial);
      return false;
    }
    const uint8_t finger =
        static_cast<uint8_t>(p.fingers[static_cast<size_t>(at - p.serials.begin())]);
    const host::Outcome o = d.ApplyCalibration(finger, file);
    if (!o.ok()) {
      Fail("demo", o.status, file.actuator_serial + ": " + o.message);
      return false;
    }
    *compensator = "calibrated, " + host::CompensatorLabel(file);
    std::fprintf(TextOut(), "  finger %d (%s): fit residual %.1f µm RMS%s%s\n", finger + 1,
                 file.actuator_serial.c_str(), file.quality.residual_rms,
                 file.quality.flags.empty() ? "" : "; note: ",
                 file.quality.flags.empty() ? "" : file.quality.flags.front().c_str());
  }
  return true;
}

}  // namespace palpa::cli
