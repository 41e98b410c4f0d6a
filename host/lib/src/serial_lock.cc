// Serial port locks: FHS lock files, TIOCEXCL and naming the process that holds a port.
#include "serial_lock.h"

#include <dirent.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/ioctl.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <fstream>

namespace palpa::host {
namespace {

std::string RealPath(const std::string& path) {
  char resolved[PATH_MAX];
  return realpath(path.c_str(), resolved) != nullptr ? std::string(resolved) : path;
}

/// "ttyACM0" for /dev/ttyACM0, "pts_3" for /dev/pts/3: the convention's name of a port.
std::string LockName(const std::string& real) {
  std::string name = real.rfind("/dev/", 0) == 0 ? real.substr(5) : real;
  if (real.rfind("/dev/", 0) != 0) name = name.substr(name.rfind('/') + 1);
  for (char& c : name) c = c == '/' ? '_' : c;
  return "LCK.." + name;
}

/// "pid 1234: palpa monitor" from /proc/PID/cmdline: the program's name and its arguments.
std::string Describe(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/cmdline", std::ios::binary);
  std::string command, word;
  while (std::getline(in, word, '\0')) {
    if (command.empty()) word = word.substr(word.rfind('/') + 1);  // npos + 1 == 0: all of it
    command += (command.empty() ? "" : " ") + word;
  }
  if (command.size() > 80) command = command.substr(0, 77) + "...";
  return "pid " + std::to_string(pid) + (command.empty() ? "" : ": " + command);
}

/// The PID in a lock file (ASCII, as the convention writes it), or 0.
pid_t ReadOwner(const std::string& file) {
  std::ifstream in(file);
  long pid = 0;
  return in >> pid && pid > 0 ? static_cast<pid_t>(pid) : 0;
}

bool Alive(pid_t pid) { return kill(pid, 0) == 0 || errno == EPERM; }

}  // namespace

std::string SerialLock::Directory() {
  const char* env = std::getenv("PALPA_LOCK_DIR");
  return env != nullptr && *env != '\0' ? env : "/run/lock";
}

Status SerialLock::Acquire(const std::string& path, std::string* holder) {
  const std::string dir = Directory();
  const std::string file = dir + "/" + LockName(RealPath(path));
  // Written whole to a file of our own, then linked into place: the lock appears complete or not
  // at all, and link() fails if another process made it first.
  const std::string mine = file + "." + std::to_string(getpid());
  const int fd = open(mine.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (fd < 0) return Status::kOk;  // no lock directory for this user: TIOCEXCL still applies
  char text[16];
  const int n = std::snprintf(text, sizeof(text), "%10d\n", static_cast<int>(getpid()));
  const bool written = n > 0 && write(fd, text, static_cast<size_t>(n)) == n;
  close(fd);
  for (int attempt = 0; written && attempt < 2; ++attempt) {
    if (link(mine.c_str(), file.c_str()) == 0) {
      unlink(mine.c_str());
      file_ = file;
      return Status::kOk;
    }
    if (errno != EEXIST) break;
    const pid_t owner = ReadOwner(file);
    if (owner != 0 && Alive(owner)) {
      unlink(mine.c_str());
      *holder = Describe(owner) + (owner == getpid() ? " (this process)" : "") + ", lock " + file;
      return Status::kBusy;
    }
    unlink(file.c_str());  // its owner is gone: a stale lock
  }
  unlink(mine.c_str());
  return Status::kOk;  // could not write a lock: TIOCEXCL still applies
}

SerialLock::~SerialLock() {
  if (!file_.empty() && ReadOwner(file_) == getpid()) unlink(file_.c_str());
}

std::string SerialHolder(const std::string& path) {
  const std::string real = RealPath(path);
  DIR* proc = opendir("/proc");
  if (proc == nullptr) return {};
  std::string found;
  while (dirent* p = readdir(proc)) {
    const pid_t pid = static_cast<pid_t>(std::atoi(p->d_name));
    if (pid <= 0 || pid == getpid()) continue;
    const std::string fds = "/proc/" + std::string(p->d_name) + "/fd";
    DIR* dir = opendir(fds.c_str());
    if (dir == nullptr) continue;
    while (dirent* f = readdir(dir)) {
      char target[PATH_MAX];
      const ssize_t n = readlink((fds + "/" + f->d_name).c_str(), target, sizeof(target) - 1);
      if (n > 0 && std::string(target, static_cast<size_t>(n)) == real) {
        found = Describe(pid);
        break;
      }
    }
    closedir(dir);
    if (!found.empty()) break;
  }
  closedir(proc);
  return found;
}

bool MakeExclusive(int fd) { return ioctl(fd, TIOCEXCL) == 0; }

}  // namespace palpa::host
