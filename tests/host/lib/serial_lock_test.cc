// Serial ports are one host's: the lock file names the holder, a stale lock is taken over, the
// open port is exclusive (TIOCEXCL), and a port held exclusively without a lock is busy and traced
// to its process.
#include <fcntl.h>
#include <pty.h>
#include <signal.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <termios.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include "palpa/host/transport.h"
#include "serial_lock.h"

#include "CppUTest/TestHarness.h"

namespace ph = palpa::host;
namespace pp = palpa::protocol;

TEST_GROUP(SerialLock) {
  int master = -1, slave = -1;
  std::string port, lock_dir;
  void setup() override {
    char name[256];
    CHECK(openpty(&master, &slave, name, nullptr, nullptr) == 0);
    port = name;
    // A lock directory of this test's own: tests running at once must not see each other's.
    char dir[] = "/tmp/palpa-locks-XXXXXX";
    CHECK(mkdtemp(dir) != nullptr);
    lock_dir = dir;
    setenv("PALPA_LOCK_DIR", lock_dir.c_str(), 1);
  }
  void teardown() override {
    unsetenv("PALPA_LOCK_DIR");
    close(slave);
    close(master);
    unlink(LockFile().c_str());
    rmdir(lock_dir.c_str());
  }
  std::string LockFile() const {
    std::string name = port.substr(5);  // "pts/3" → "pts_3"
    for (char& c : name) c = c == '/' ? '_' : c;
    return lock_dir + "/LCK.." + name;
  }
};

TEST(SerialLock, ASecondOpenIsBusyAndNamesTheHolder) {
  auto first = ph::OpenTransport("serial:" + port);
  CHECK_TEXT(first.ok(), first.message.c_str());
  std::ifstream lock(LockFile());
  long owner = 0;
  CHECK(static_cast<bool>(lock >> owner));
  LONGS_EQUAL(getpid(), owner);  // the convention: the holder's PID in ASCII
  auto second = ph::OpenTransport("serial:" + port);
  LONGS_EQUAL((int)pp::Status::kBusy, (int)second.status);
  CHECK_TEXT(second.message.find("busy: another host holds the board") == 0,
             second.message.c_str());
  CHECK_TEXT(second.message.find("pid " + std::to_string(getpid())) != std::string::npos,
             second.message.c_str());
  first.value.reset();  // closed: the lock goes with it
  CHECK(access(LockFile().c_str(), F_OK) != 0);
  auto third = ph::OpenTransport("serial:" + port);
  CHECK_TEXT(third.ok(), third.message.c_str());
}

TEST(SerialLock, AStaleLockIsTakenOver) {
  const pid_t gone = fork();
  if (gone == 0) _exit(0);
  waitpid(gone, nullptr, 0);  // a PID that no process has any more
  std::ofstream(LockFile()) << "     " << gone << "\n";
  auto t = ph::OpenTransport("serial:" + port);
  CHECK_TEXT(t.ok(), t.message.c_str());
  std::ifstream lock(LockFile());
  long owner = 0;
  CHECK(static_cast<bool>(lock >> owner));
  LONGS_EQUAL(getpid(), owner);
}

TEST(SerialLock, TheOpenPortIsExclusive) {
  auto t = ph::OpenTransport("serial:" + port);
  CHECK_TEXT(t.ok(), t.message.c_str());
  int exclusive = 0;
  CHECK(ioctl(slave, TIOCGEXCL, &exclusive) == 0);  // the flag belongs to the terminal
  LONGS_EQUAL(1, exclusive);
}

TEST(SerialLock, APortHeldWithoutALockIsTracedToItsProcess) {
  int ready[2];
  CHECK(pipe(ready) == 0);
  const pid_t holder = fork();
  if (holder == 0) {
    const int fd = open(port.c_str(), O_RDWR | O_NOCTTY);
    const char c = fd >= 0 ? 'y' : 'n';
    if (write(ready[1], &c, 1) != 1) _exit(1);
    pause();
    _exit(0);
  }
  char c = 0;
  CHECK(read(ready[0], &c, 1) == 1 && c == 'y');
  const std::string named = ph::SerialHolder(port);
  kill(holder, SIGKILL);
  waitpid(holder, nullptr, 0);
  close(ready[0]);
  close(ready[1]);
  CHECK_TEXT(named.find("pid " + std::to_string(holder)) == 0, named.c_str());
}

TEST(SerialLock, APortOpenedExclusivelyWithoutALockIsBusy) {
  // Another program holds the port exclusively and took no lock. TIOCEXCL binds all but root,
  // so the second opener runs as an ordinary user (nobody), in a process of its own.
  CHECK(ioctl(slave, TIOCEXCL) == 0);
  CHECK(chmod(port.c_str(), 0666) == 0 && chmod(lock_dir.c_str(), 0777) == 0);
  int answer[2];
  CHECK(pipe(answer) == 0);
  const pid_t opener = fork();
  if (opener == 0) {
    if (getuid() == 0 && (setgid(65534) != 0 || setuid(65534) != 0)) _exit(2);
    const auto t = ph::OpenTransport("serial:" + port);
    const std::string said = std::to_string(static_cast<int>(t.status)) + " " + t.message;
    _exit(write(answer[1], said.data(), said.size()) == static_cast<ssize_t>(said.size()) ? 0 : 1);
  }
  close(answer[1]);
  int status = 0;
  waitpid(opener, &status, 0);
  char said[512] = {};
  const ssize_t n = read(answer[0], said, sizeof(said) - 1);
  close(answer[0]);
  CHECK_TEXT(WIFEXITED(status) && WEXITSTATUS(status) == 0, said);
  CHECK(n > 0);
  const std::string text(said);
  CHECK_TEXT(text.find(std::to_string(static_cast<int>(pp::Status::kBusy)) +
                       " busy: another host "
                       "holds the board (serial:" +
                       port + " is open exclusively") == 0,
             said);
}
