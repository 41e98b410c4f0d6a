// The running simulated board's record: a JSON file naming its process, address and flash.
#include "sim_state.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "palpa/host/file_write.h"
#include "palpa/host/transport.h"

namespace palpa::cli {
namespace {

std::string RecordPath() { return SimStateDir() + "/sim.json"; }

std::string ReadText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

/// The process `pid` is alive (not a zombie) and is palpa-sim keeping `flash`: a pid reused by
/// another program is never taken for it.
bool IsOurSim(int pid, const std::string& flash) {
  if (pid <= 0 || kill(pid, 0) != 0) return false;
  const std::string stat = ReadText("/proc/" + std::to_string(pid) + "/stat");
  const size_t paren = stat.rfind(')');
  if (paren == std::string::npos || (paren + 2 < stat.size() && stat[paren + 2] == 'Z'))
    return false;
  std::string cmdline = ReadText("/proc/" + std::to_string(pid) + "/cmdline");
  for (char& c : cmdline) c = c == '\0' ? ' ' : c;
  return cmdline.find("palpa-sim") != std::string::npos &&
         cmdline.find(" " + flash + " ") != std::string::npos;
}

std::string UtcNow() {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char text[32];
  std::strftime(text, sizeof(text), "%Y-%m-%dT%H:%M:%SZ", &utc);
  return text;
}

}  // namespace

std::string SimStateDir() {
  if (const char* dir = std::getenv("PALPA_STATE_DIR"); dir != nullptr && *dir != '\0') return dir;
  if (const char* state = std::getenv("XDG_STATE_HOME"); state != nullptr && *state != '\0')
    return std::string(state) + "/palpa";
  const char* home = std::getenv("HOME");
  return std::string(home != nullptr ? home : ".") + "/.local/state/palpa";
}

std::optional<RunningSim> FindRunningSim(std::string* gone) {
  const std::string text = ReadText(RecordPath());
  if (text.empty()) return std::nullopt;
  const nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
  RunningSim sim;
  if (j.is_object() && j.value("pid", 0) > 0) {
    sim.pid = j.value("pid", 0);
    sim.uri = j.value("uri", "");
    sim.config = j.value("config", "");
    sim.flash = j.value("flash", "");
    sim.log = j.value("log", "");
    sim.started = j.value("started", "");
    if (IsOurSim(sim.pid, sim.flash)) return sim;
  }
  std::remove(RecordPath().c_str());
  if (gone != nullptr) {
    *gone = "the simulated board started by 'palpa sim start'" +
            (sim.pid > 0 ? " (pid " + std::to_string(sim.pid) + ")" : std::string()) +
            " is no longer running";
  }
  return std::nullopt;
}

host::Result<RunningSim> StartSim(const std::string& config, const std::string& flash,
                                  const std::vector<std::string>& options) {
  using protocol::Status;
  std::error_code ec;
  std::filesystem::create_directories(SimStateDir(), ec);
  if (ec) return {Status::kIoError, SimStateDir() + ": " + ec.message()};
  const std::string log = SimStateDir() + "/sim.log";
  std::remove(log.c_str());  // what the last run printed must not pass for this one's address
  const std::string program = host::FindPalpaSim();
  std::vector<std::string> args = {program,           "--config", config, "--listen",
                                   "tcp:127.0.0.1:0", "--flash",  flash};
  args.insert(args.end(), options.begin(), options.end());
  const pid_t child = fork();
  if (child < 0) return {Status::kUnavailable, "cannot start palpa-sim (fork failed)"};
  if (child == 0) {
    // A process of its own that outlives this command: its own session, no terminal, output to
    // the log.
    setsid();
    const int in = open("/dev/null", O_RDONLY);
    const int to = open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (in < 0 || to < 0) _exit(126);
    dup2(in, STDIN_FILENO);
    dup2(to, STDOUT_FILENO);
    dup2(to, STDERR_FILENO);
    for (int fd = 3; fd < 1024; ++fd) close(fd);
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    execvp(program.c_str(), argv.data());
    _exit(127);
  }
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  std::string text;
  while (std::chrono::steady_clock::now() < deadline) {
    text = ReadText(log);
    const size_t at = text.find("listening on tcp:");
    if (at != std::string::npos && text.find('\n', at) != std::string::npos) {
      RunningSim out;
      out.pid = child;
      out.uri = text.substr(at + 13, text.find('\n', at) - at - 13);
      out.config = config;
      out.flash = flash;
      out.log = log;
      out.started = UtcNow();
      const nlohmann::json record = {{"pid", out.pid},       {"uri", out.uri},
                                     {"config", out.config}, {"flash", out.flash},
                                     {"log", out.log},       {"started", out.started}};
      const host::Outcome kept = host::WriteFileWhole(RecordPath(), record.dump(2) + "\n");
      if (!kept.ok()) {
        kill(child, SIGTERM);
        return kept;
      }
      return out;
    }
    int status = 0;
    if (waitpid(child, &status, WNOHANG) == child) break;  // it stopped: the log says why
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  kill(child, SIGKILL);
  waitpid(child, nullptr, 0);
  while (!text.empty() && text.back() == '\n') text.pop_back();
  return {Status::kUnavailable,
          "palpa-sim (" + program + ") did not start" + (text.empty() ? "" : ": " + text)};
}

host::Outcome StopSim(const RunningSim& sim) {
  if (IsOurSim(sim.pid, sim.flash)) {
    kill(sim.pid, SIGTERM);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
    while (IsOurSim(sim.pid, sim.flash) && std::chrono::steady_clock::now() < deadline)
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    if (IsOurSim(sim.pid, sim.flash)) kill(sim.pid, SIGKILL);
    for (int i = 0; i < 100 && IsOurSim(sim.pid, sim.flash); ++i)
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    if (IsOurSim(sim.pid, sim.flash)) {
      return host::Outcome::Fail(protocol::Status::kBusy,
                                 "palpa-sim (pid " + std::to_string(sim.pid) + ") does not stop");
    }
  }
  std::remove(RecordPath().c_str());
  return {};
}

}  // namespace palpa::cli
