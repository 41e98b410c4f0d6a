// A calibration session: the output directory, the journal, the previous calibration, the run
// and its files, in the order palpa calibrate and applications run them.
#include "palpa/calibration/session.h"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <ctime>

#include "palpa/calibration/report.h"
#include "palpa/host/file_write.h"

namespace palpa::calibration {
namespace {

using protocol::Status;

std::string UtcNow() {
  const std::time_t t = std::time(nullptr);
  char b[32];
  std::strftime(b, sizeof(b), "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
  return b;
}

host::Outcome Failed(Status status, std::string message) {
  return host::Outcome{status, std::move(message), {}};
}

}  // namespace

Session::Session(const Rig& rig, std::string serial, uint32_t board_id, bool jamming,
                 SessionOptions options)
    : rig_(rig),
      serial_(std::move(serial)),
      board_id_(board_id),
      jamming_(jamming),
      options_(std::move(options)) {}

SweepCapacity Session::Sweep() const { return SweepFor(options_.protocol, jamming_); }

host::Outcome Session::CheckSweep() const {
  const std::string why = Sweep().Refusal(options_.protocol.compensator);
  if (why.empty() || options_.allow_fallback) return {};
  return Failed(Status::kInvalidArgument, why);
}

host::Outcome Session::OpenOutput() {
  if (options_.out_dir.empty()) return {};
  struct stat st {};
  // Another run (of another finger) may have made it meanwhile: only a failure to have it counts.
  if (stat(options_.out_dir.c_str(), &st) != 0 && mkdir(options_.out_dir.c_str(), 0755) != 0 &&
      !(errno == EEXIST && stat(options_.out_dir.c_str(), &st) == 0 && S_ISDIR(st.st_mode))) {
    return Failed(Status::kIoError,
                  "cannot create " + options_.out_dir + ": " + std::strerror(errno));
  }
  const std::string path = base() + ".journal.json";
  journal_.save = [path, notify = options_.journal_not_saved](const Journal& j) {
    const host::Outcome saved = host::WriteFileWhole(path, j.state.dump());
    if (!saved.ok() && notify) notify(saved.message);
  };
  return {};
}

host::Outcome Session::Resume() {
  const std::string path = base() + ".journal.json";
  struct stat journal_stat;
  if (options_.out_dir.empty() || lstat(path.c_str(), &journal_stat) != 0)
    return Failed(Status::kNotFound, "no journal " + path);
  auto state = LoadJournal(path);
  if (!state.ok()) return Failed(Status::kBadValue, state.message);
  journal_.state = std::move(state.value);
  return {};
}

host::Outcome Session::LoadPrevious() {
  const std::string path = options_.previous.empty() ? base() + ".json" : options_.previous;
  if (options_.previous.empty() && (options_.out_dir.empty() || access(path.c_str(), F_OK) != 0))
    return {};
  auto previous = host::LoadCalibration(path);
  if (!previous.ok()) return Failed(Status::kBadValue, "previous calibration " + previous.message);
  previous_ = std::move(previous.value);
  if (previous_->actuator_serial != serial_) {
    const std::string other = previous_->actuator_serial;
    previous_.reset();
    return Failed(Status::kInvalidArgument, path + ": calibrates " + other + ", not " + serial_);
  }
  return {};
}

host::Outcome Session::Run(const std::function<void(const Progress&)>& progress) {
  RunInfo info{serial_,
               board_id_,
               options_.date ? *options_.date : UtcNow(),
               rig_.name,
               options_.out_dir.empty() ? "" : serial_ + ".csv",
               previous_ ? &*previous_ : nullptr};
  info.simulation = options_.simulation;
  run_ = CalibrationRun{};
  stopped_ = false;
  const RigStatus s =
      RunCalibration(rig_, options_.finger, options_.protocol, info, journal_, progress, &run_);
  if (!s.ok()) {
    stopped_ = true;
    return Failed(s.status, s.message);  // the rig's code: a limit, a lost device, a fault
  }
  if (!run_.fit.ok() && !options_.allow_fallback)
    return Failed(Status::kBadValue, "the compensator could not be fitted: " + run_.fit.error);
  return {};
}

host::Outcome Session::Write() {
  if (options_.out_dir.empty()) return {};
  std::string csv;
  for (const std::string& row : run_.csv) csv += row + "\n";
  host::Outcome o = host::WriteFileWhole(base() + ".csv", csv);
  if (o.ok()) o = host::SaveCalibration(run_.file, base() + ".json");
  if (o.ok()) o = host::WriteFileWhole(base() + ".html", RenderReport(run_));
  if (!o.ok()) {
    return Failed(Status::kIoError,
                  "cannot write the results in " + options_.out_dir + ": " + o.message);
  }
  unlink((base() + ".journal.json").c_str());
  return {};
}

host::Outcome Session::Calibrate(const std::function<void(const Progress&)>& progress) {
  host::Outcome o = CheckSweep();
  if (o.ok()) o = OpenOutput();
  if (o.ok() && options_.resume) o = Resume();
  if (o.ok()) o = LoadPrevious();
  if (o.ok()) o = Run(progress);
  if (o.ok()) o = Write();
  return o;
}

std::vector<std::string> Session::files() const {
  if (options_.out_dir.empty()) return {};
  return {base() + ".json", base() + ".csv", base() + ".html"};
}

nlohmann::ordered_json Session::Summary(bool applied, int number_from) const {
  const host::CalibrationFile& file = run_.file;
  nlohmann::ordered_json checks = nlohmann::ordered_json::array();
  for (const host::QualityCheck& k : file.quality.checks)
    checks.push_back({{"name", k.name}, {"passed", k.passed}, {"detail", k.detail}});
  nlohmann::ordered_json result = {{"calibrated", serial_},
                                   {"finger", options_.finger + number_from},
                                   {"files", files()},
                                   {"compensator", host::CompensatorLabel(file)},
                                   {"operators_with_weight", run_.fit.operators_used},
                                   {"residual_rms", file.quality.residual_rms},
                                   {"checks", checks},
                                   {"applied", applied}};
  if (file.simulation) {
    result["simulation"] = {{"actuator_unit", file.simulation->actuator_unit},
                            {"seed", file.simulation->seed},
                            {"plant_level", file.simulation->plant_level},
                            {"effects", file.simulation->effects}};
  }
  return result;
}

}  // namespace palpa::calibration
