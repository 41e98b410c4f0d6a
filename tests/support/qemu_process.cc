// QEMU child process for the Cortex-M tests.
#include "qemu_process.h"

#include <fcntl.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <thread>

#include "sim_process.h"

namespace palpa::testing {

bool QemuProcess::Start(const std::string& qemu, const std::vector<std::string>& args) {
  port_ = FreeTcpPort();
  const std::string serial = "tcp:127.0.0.1:" + std::to_string(port_) + ",server=on,wait=on";
  std::vector<std::string> argv = {
      qemu,       "-M",   "mps2-an386",          "-nographic",
      "-monitor", "none", "-semihosting-config", "enable=on,target=native",
      "-serial",  serial};
  argv.insert(argv.end(), args.begin(), args.end());
  std::vector<char*> raw;  // before the fork: the child may only call what is async-signal-safe
  for (std::string& a : argv) raw.push_back(a.data());
  raw.push_back(nullptr);
  pid_ = fork();
  if (pid_ == 0) {
    const int null = open("/dev/null", O_WRONLY);  // QEMU's "waiting for connection" notes
    if (null >= 0) dup2(null, STDERR_FILENO);
    execv(qemu.c_str(), raw.data());
    _exit(127);
  }
  for (int i = 0; i < 100; ++i) {  // until QEMU listens; the first connection starts the CPU
    const int fd = socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(static_cast<uint16_t>(port_));
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    const bool up = connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof(a)) == 0;
    close(fd);  // QEMU listens again for the next client (the host under test)
    if (up) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return false;
}

QemuProcess::~QemuProcess() {
  if (pid_ > 0) {
    kill(pid_, SIGKILL);
    waitpid(pid_, nullptr, 0);
  }
}

}  // namespace palpa::testing
