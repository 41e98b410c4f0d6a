// The simulator transport: palpa-sim found and started as a child process, reached over TCP, and
// stopped when the transport closes.
#include <dlfcn.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <climits>
#include <cstring>
#include <vector>

#include "fd_transport.h"

namespace palpa::host {

SimTransport::~SimTransport() {
  if (fd_ >= 0) close(fd_);
  fd_ = -1;
  if (child_ > 0) {
    kill(child_, SIGTERM);
    int status = 0;
    for (int i = 0; i < 100 && waitpid(child_, &status, WNOHANG) == 0; ++i) usleep(10000);
    if (waitpid(child_, &status, WNOHANG) == 0) {
      kill(child_, SIGKILL);
      waitpid(child_, &status, 0);
    }
  }
}

std::string FindPalpaSim() {
  if (const char* env = getenv("PALPA_SIM"); env != nullptr && *env != '\0') return env;
  char self[PATH_MAX];
  const ssize_t n = readlink("/proc/self/exe", self, sizeof(self) - 1);
  if (n > 0) {
    self[n] = '\0';
    std::string dir(self);
    dir = dir.substr(0, dir.rfind('/'));
    for (const std::string& candidate : {dir + "/palpa-sim", dir + "/../bin/palpa-sim"}) {
      if (access(candidate.c_str(), X_OK) == 0) return candidate;
    }
  }
#ifdef PALPA_SIM_FROM_LIBDIR
  // An installed libpalpa loaded by another program (python3, an application): palpa-sim is
  // installed with it, at the same place relative to the library.
  Dl_info library{};
  if (dladdr(reinterpret_cast<void*>(&FindPalpaSim), &library) != 0 && library.dli_fname) {
    std::string dir(library.dli_fname);
    if (dir.find('/') != std::string::npos) {
      dir = dir.substr(0, dir.rfind('/'));
      const std::string candidate = dir + "/" PALPA_SIM_FROM_LIBDIR;
      if (access(candidate.c_str(), X_OK) == 0) return candidate;
    }
  }
#endif
#ifdef PALPA_SIM_BUILD_PATH
  if (access(PALPA_SIM_BUILD_PATH, X_OK) == 0) return PALPA_SIM_BUILD_PATH;
#endif
  return "palpa-sim";
}

Result<std::unique_ptr<Transport>> OpenSim(const DeviceUri& uri, std::string* truth_address) {
  std::vector<std::string> options;
  if (const char* args_env = getenv("PALPA_SIM_ARGS");
      args_env != nullptr) {  // e.g. "--plant 1 --speed 10"
    const std::string a(args_env);
    size_t at = 0;
    while (at < a.size()) {
      const size_t sp = a.find(' ', at);
      const std::string word = a.substr(at, sp == std::string::npos ? std::string::npos : sp - at);
      if (!word.empty()) options.push_back(word);
      if (sp == std::string::npos) break;
      at = sp + 1;
    }
  }
  return LaunchSim(uri.config, options, truth_address);
}

Result<std::unique_ptr<Transport>> LaunchSim(const std::string& config,
                                             const std::vector<std::string>& options,
                                             std::string* truth_address, std::string* rig_address,
                                             std::string* announcement) {
  DeviceUri uri;
  uri.config = config;
  const std::string program = FindPalpaSim();
  int out[2];
  if (pipe(out) != 0) {
    return {Status::kIoError, std::string("sim: pipe: ") + std::strerror(errno)};
  }
  const pid_t child = fork();
  if (child == 0) {
    // A caller that leaves signals to a thread of its own blocks them (the palpa CLI does): the
    // simulator must still stop on SIGTERM, its parent's death included.
    sigset_t none;
    sigemptyset(&none);
    sigprocmask(SIG_SETMASK, &none, nullptr);
    prctl(PR_SET_PDEATHSIG, SIGTERM);  // never outlive the process that started it
    dup2(out[1], STDOUT_FILENO);
    close(out[0]);
    std::vector<std::string> args = {program, "--config", uri.config, "--listen",
                                     "tcp:127.0.0.1:0"};
    args.insert(args.end(), options.begin(), options.end());
    if (truth_address != nullptr) {
      args.push_back("--truth");
      args.push_back("tcp:127.0.0.1:0");
    }
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    execvp(program.c_str(), argv.data());
    _exit(127);
  }
  close(out[1]);
  std::string text;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  std::string address;
  while (std::chrono::steady_clock::now() < deadline) {
    pollfd p{out[0], POLLIN, 0};
    if (poll(&p, 1, 100) <= 0) continue;
    char buffer[512];
    const ssize_t n = read(out[0], buffer, sizeof(buffer));
    if (n <= 0) break;
    text.append(buffer, static_cast<size_t>(n));
    const size_t at = text.find("listening on tcp:");
    const size_t truth_at = text.find("truth on ");
    const bool truth_ready =
        truth_address == nullptr ||
        (truth_at != std::string::npos && text.find('\n', truth_at) != std::string::npos);
    const size_t rig_at = text.find("by Modbus on ");
    const bool rig_ready = rig_address == nullptr || (rig_at != std::string::npos &&
                                                      text.find('\n', rig_at) != std::string::npos);
    if (at != std::string::npos && text.find('\n', at) != std::string::npos && truth_ready &&
        rig_ready) {
      address = text.substr(at + 17, text.find('\n', at) - at - 17);
      if (truth_address != nullptr)
        *truth_address = text.substr(truth_at + 9, text.find('\n', truth_at) - truth_at - 9);
      if (rig_address != nullptr)
        *rig_address = text.substr(rig_at + 13, text.find('\n', rig_at) - rig_at - 13);
      break;
    }
  }
  close(out[0]);
  if (address.empty()) {
    kill(child, SIGKILL);
    waitpid(child, nullptr, 0);
    return {Status::kUnavailable, "sim:" + uri.config + ": palpa-sim (" + program +
                                      ") did not start" +
                                      (text.empty() ? std::string() : ": " + text)};
  }
  if (announcement != nullptr) *announcement = text.substr(0, text.find('\n'));
  DeviceUri tcp;
  tcp.host = address.substr(0, address.rfind(':'));
  tcp.port = static_cast<uint16_t>(std::stoi(address.substr(address.rfind(':') + 1)));
  const Result<int> fd = ConnectTcp(tcp);
  if (!fd.ok()) {
    kill(child, SIGKILL);
    waitpid(child, nullptr, 0);
    return fd.outcome();
  }
  // The description carries what palpa-sim said it runs (its plant's unit and seed), so a record
  // made through this link can say which simulated board it was.
  const std::string said = text.substr(0, text.find('\n'));
  const std::string runs = said.rfind("palpa-sim: ", 0) == 0 ? said.substr(11) : said;
  return std::unique_ptr<Transport>(new SimTransport(
      fd.value, child, "sim:" + uri.config + " (palpa-sim on tcp:" + address + ": " + runs + ")"));
}

Result<std::unique_ptr<Transport>> OpenTransport(const std::string& uri,
                                                 std::string* sim_truth_address) {
  const Result<DeviceUri> uri_parsed = ParseDeviceUri(uri);
  if (!uri_parsed.ok()) return uri_parsed.outcome();
  const DeviceUri& parsed = uri_parsed.value;
  switch (parsed.kind) {
    case DeviceUri::Kind::kSim:
      return OpenSim(parsed, sim_truth_address);
    case DeviceUri::Kind::kSerial:
      return OpenSerial(parsed);
    case DeviceUri::Kind::kTcp:
      return OpenTcp(parsed);
    case DeviceUri::Kind::kHid:
      return OpenHid(parsed);
    case DeviceUri::Kind::kUsb:
      return OpenUsb(parsed);
  }
  return {Status::kInvalidArgument, uri + ": not a device URI"};
}

}  // namespace palpa::host
