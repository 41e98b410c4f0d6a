// palpa-sim as a test's child process: started, its addresses read from what it prints, its
// output drained for its whole life, stopped.
#include "sim_process.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <thread>

namespace palpa::testing {

namespace {

/// A port of this socket type that the kernel gave out on 127.0.0.1 and took back.
int FreeLoopbackPort(int type) {
  const int fd = socket(AF_INET, type, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof(a));
  socklen_t n = sizeof(a);
  getsockname(fd, reinterpret_cast<sockaddr*>(&a), &n);
  close(fd);
  return ntohs(a.sin_port);
}

}  // namespace

int FreeTcpPort() { return FreeLoopbackPort(SOCK_STREAM); }

int FreeUdpPort() { return FreeLoopbackPort(SOCK_DGRAM); }

/// Reads the child's output until it closes it or the SimProcess goes, keeping the tail.
struct SimProcess::Drain {
  static constexpr size_t kKept = 64 * 1024;
  explicit Drain(int fd) : fd_(fd) {
    if (pipe2(wake_, O_CLOEXEC) != 0) wake_[0] = wake_[1] = -1;
    thread_ = std::thread([this] { Run(); });
  }
  ~Drain() {
    if (wake_[1] >= 0) (void)!write(wake_[1], "x", 1);
    thread_.join();
    for (int fd : wake_)
      if (fd >= 0) close(fd);
  }
  void Run() {
    char buffer[4096];
    for (;;) {
      pollfd p[2] = {{fd_, POLLIN, 0}, {wake_[0], POLLIN, 0}};
      if (poll(p, wake_[0] >= 0 ? 2 : 1, -1) < 0) {
        if (errno == EINTR) continue;
        return;
      }
      if (p[1].revents != 0) return;  // the SimProcess is going
      const ssize_t n = read(fd_, buffer, sizeof(buffer));
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) return;  // every writer closed it: the child and what it started are gone
      std::lock_guard<std::mutex> hold(mutex);
      tail.append(buffer, static_cast<size_t>(n));
      if (tail.size() > kKept) tail.erase(0, tail.size() - kKept);
    }
  }
  int fd_;
  int wake_[2];
  std::thread thread_;
  std::mutex mutex;
  std::string tail;
};

SimProcess::SimProcess() = default;

std::string SimProcess::later_output() const {
  if (!drain_) return {};
  std::lock_guard<std::mutex> hold(drain_->mutex);
  return drain_->tail;
}

bool SimProcess::Start(const std::vector<std::string>& args, const char* program, int timeout_ms) {
  // Built before the fork: the child of a process with threads may only call what is
  // async-signal-safe (an allocation can wait forever on a lock another thread held).
  std::vector<char*> argv;
  // $PALPA_SIM: another palpa-sim than the build's (inside the real-kernel guest).
  const char* path = program != nullptr                    ? program
                     : std::getenv("PALPA_SIM") != nullptr ? std::getenv("PALPA_SIM")
                                                           : PALPA_SIM_PATH;
  argv.push_back(const_cast<char*>(path));
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  drain_.reset();  // a SimProcess started again reads only its new child
  if (out_fd_ >= 0) close(out_fd_);
  out_fd_ = -1;
  int out[2];
  if (pipe(out) != 0) return false;
  pid_ = fork();
  if (pid_ == 0) {
    prctl(PR_SET_PDEATHSIG, SIGTERM);  // never outlive the process that started it
    dup2(out[1], STDOUT_FILENO);
    dup2(out[1], STDERR_FILENO);
    close(out[0]);
    execv(path, argv.data());
    _exit(127);
  }
  close(out[1]);
  out_fd_ = out[0];
  // From here on the output is read whatever Start answers: a child that did not announce itself
  // in time may still be running and writing.
  struct DrainAfter {
    SimProcess& p;
    ~DrainAfter() { p.drain_ = std::make_unique<Drain>(p.out_fd_); }
  } drain_after{*this};
  std::string& text = output_;
  text.clear();
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  while (std::chrono::steady_clock::now() < deadline) {
    pollfd p{out_fd_, POLLIN, 0};
    if (poll(&p, 1, 100) <= 0) continue;
    char buffer[512];
    const ssize_t n = read(out_fd_, buffer, sizeof(buffer));
    if (n <= 0) return false;
    text.append(buffer, static_cast<size_t>(n));
    // Each announced address is a whole line: "PREFIX ADDRESS\n".
    auto line_after = [&text](const char* prefix, std::string* found) {
      const size_t at = text.find(prefix);
      if (at == std::string::npos) return false;
      const size_t start = at + std::strlen(prefix), end = text.find('\n', start);
      if (end == std::string::npos) return false;
      *found = text.substr(start, end - start);
      return true;
    };
    auto wants = [&args](const char* option) {
      return std::find(args.begin(), args.end(), option) != args.end();
    };
    if (line_after("listening on ", &address_) &&
        (!wants("--truth") || line_after("truth on ", &truth_address_)) &&
        (!wants("--rig-modbus") || line_after("by Modbus on ", &rig_address_)) &&
        (!wants("--rig-netft") || line_after("as Net F/T on ", &netft_address_))) {
      return true;
    }
  }
  return false;
}

int SimProcess::Stop() {
  if (pid_ <= 0) return -1;
  kill(pid_, SIGTERM);
  int status = 0;
  for (int i = 0; i < 100; ++i) {
    if (waitpid(pid_, &status, WNOHANG) == pid_) {
      pid_ = -1;
      return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    }
    usleep(20000);
  }
  kill(pid_, SIGKILL);  // never leave a simulator behind
  waitpid(pid_, &status, 0);
  pid_ = -1;
  return -1;
}

int SimProcess::WaitExit(int timeout_ms) {
  if (pid_ <= 0) return -2;
  int status = 0;
  for (int waited = 0; waited <= timeout_ms; waited += 20) {
    if (waitpid(pid_, &status, WNOHANG) == pid_) {
      pid_ = -1;
      return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    }
    usleep(20000);
  }
  return -2;
}

SimProcess::~SimProcess() {
  Stop();
  drain_.reset();
  if (out_fd_ >= 0) close(out_fd_);
}

}  // namespace palpa::testing
