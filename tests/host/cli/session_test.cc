// Sessions as hosts meet them, on palpa-sim and on the Cortex-M image under QEMU (behind a shared
// line, so a second host reaches its UART): the palpa commands in sequence with pauses of twice
// the host-silence timeout, a second command told busy, every way a command ends (normally,
// SIGINT, SIGTERM, SIGHUP: no fault; SIGKILL: host_silence), a C program and a Python script that
// close and reopen, and stale, foreign and second-host frames that keep nothing actuated.
#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_run.h"
#include "mini_client.h"
#include "palpa/protocol/faults.h"
#include "qemu_process.h"
#include "shared_line.h"
#include "sim_process.h"

#include "CppUTest/TestHarness.h"

namespace pp = palpa::protocol;
using palpa::testing::Has;
using palpa::testing::MiniClient;
using palpa::testing::ReceivedFrame;
using palpa::testing::Run;
using palpa::testing::Shell;

namespace {

constexpr int kPauseMs = 200;  // twice the boards' 100 ms host-silence timeout

void Pause(int ms) { std::this_thread::sleep_for(std::chrono::milliseconds(ms)); }

/// A `palpa` command running in the background, its output read until a line says it holds.
class Background {
 public:
  Background(const std::string& device, const std::vector<std::string>& args) {
    // Built before the fork: the child of a process with threads (a shared line's) may only
    // call what is async-signal-safe. An allocation there waited forever on the allocator's lock
    // that another thread held at the fork, and the command never started.
    std::vector<std::string> argv = {PALPA_CLI_PATH, "--device", device};
    argv.insert(argv.end(), args.begin(), args.end());
    std::vector<char*> raw;
    for (std::string& a : argv) raw.push_back(a.data());
    raw.push_back(nullptr);
    int out[2];
    CHECK(pipe(out) == 0);
    pid_ = fork();
    if (pid_ == 0) {
      dup2(out[1], STDOUT_FILENO);
      dup2(out[1], STDERR_FILENO);
      close(out[0]);
      execv(PALPA_CLI_PATH, raw.data());
      _exit(127);
    }
    close(out[1]);
    fd_ = out[0];
  }
  ~Background() {
    if (pid_ > 0) {
      kill(pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
    }
    close(fd_);
  }
  /// Waits (up to 10 s) for `text` in the command's output.
  bool WaitFor(const std::string& text) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (output_.find(text) == std::string::npos && std::chrono::steady_clock::now() < end) {
      char buffer[512];
      fcntl(fd_, F_SETFL, O_NONBLOCK);
      const ssize_t n = read(fd_, buffer, sizeof(buffer));
      if (n > 0) output_.append(buffer, static_cast<size_t>(n));
      if (n <= 0) Pause(5);
    }
    return output_.find(text) != std::string::npos;
  }
  const std::string& output() const { return output_; }
  /// Sends `signal` and returns the exit code (128 + the signal when killed by it), within 3 s.
  int Stop(int signal) {
    kill(pid_, signal);
    int status = 0;
    for (int i = 0; i < 300 && waitpid(pid_, &status, WNOHANG) == 0; ++i) Pause(10);
    pid_ = -1;
    fcntl(fd_, F_SETFL, O_NONBLOCK);  // what it wrote on the way out
    char buffer[512];
    for (ssize_t n; (n = read(fd_, buffer, sizeof(buffer))) > 0;)
      output_.append(buffer, static_cast<size_t>(n));
    return WIFEXITED(status) ? WEXITSTATUS(status)
                             : (WIFSIGNALED(status) ? 128 + WTERMSIG(status) : -1);
  }

 private:
  pid_t pid_ = -1;
  int fd_ = -1;
  std::string output_;
};

/// A board under test and where its hosts connect.
class Target {
 public:
  virtual ~Target() = default;
  virtual std::string address() const = 0;
  Run Palpa(const std::string& args) const {
    return Shell(std::string(PALPA_CLI_PATH) + " --device " + address() + " " + args);
  }
  /// The latched faults, as `palpa --json info` reports them.
  uint32_t Faults() const {
    const Run r = Palpa("--json info");
    LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
    return nlohmann::json::parse(r.output)["board"]["fault_bitmap"].get<uint32_t>();
  }
  /// The latched faults once they are `expected`, or after 3 s (a board whose time runs behind
  /// real time, QEMU on a loaded machine, takes longer than its timeout in real time).
  uint32_t FaultsBecome(uint32_t expected) const {
    uint32_t faults = Faults();
    for (int i = 0; i < 30 && faults != expected; ++i) {
      Pause(100);
      faults = Faults();
    }
    return faults;
  }
};

class SimTarget final : public Target {
 public:
  SimTarget() { CHECK(sim_.Start({"--config", "thesis-5finger", "--listen", "tcp:127.0.0.1:0"})); }
  std::string address() const override { return sim_.address(); }

 private:
  palpa::testing::SimProcess sim_;
};

class QemuTarget final : public Target {
 public:
  // Time paced by instructions (32 ns each, about the MPS2's 25 MHz) and never ahead of real
  // time: on a loaded machine, QEMU on the host's clock loses the CPU for longer than the 30 ms
  // watchdog now and then, and the image resets (unexpected_reset) in the middle of a sequence.
  QemuTarget() {
    CHECK_TEXT(
        access(PALPA_MPS2_IMAGE, R_OK) == 0 &&
            qemu_.Start(PALPA_QEMU, {"-icount", "shift=5,align=on", "-kernel", PALPA_MPS2_IMAGE}),
        "QEMU or the mps2 image is missing (build the mps2 preset)");
    CHECK(line_.Start(qemu_.address()));
  }
  std::string address() const override { return line_.address(); }

 private:
  palpa::testing::QemuProcess qemu_;
  palpa::testing::SharedLine line_;
};

const uint32_t kHostSilence = pp::FaultBit(pp::Fault::kHostSilence);

/// The sequences: nothing that ends cleanly leaves a fault, however long the pause.
void CommandsInSequence(const Target& t) {
  Run r = t.Palpa("info");
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  r = t.Palpa("set 1=L2");
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  CHECK_TEXT(Has(r, "the fingers return to safe now"), r.output.c_str());
  CHECK_FALSE(Has(r, "palpa monitor"));  // no longer suggested: it could not share the board
  Pause(kPauseMs);
  r = t.Palpa("set 1=L2");  // was: "the board did not apply the targets: faulted"
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  Pause(kPauseMs);
  r = t.Palpa("clear");
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  Pause(kPauseMs);
  r = t.Palpa("set 1=L2");  // was: faulted again ("clear" latched it anew on exit)
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  r = t.Palpa("line 1=30");
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  Pause(kPauseMs);
  LONGS_EQUAL(0, t.Faults());
}

/// A held board is busy for a second command; every way the holder ends by a signal closes its
/// session: no fault, and the next command gets the board at once.
void BusyAndSignals(const Target& t) {
  for (const int signal : {SIGINT, SIGTERM, SIGHUP}) {
    Background hold(t.address(), {"set", "1=L2", "--hold", "8"});
    CHECK_TEXT(hold.WaitFor("holding for 8 s"), hold.output().c_str());
    const auto start = std::chrono::steady_clock::now();
    const Run monitor = t.Palpa("monitor --duration 1");
    const double took =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    LONGS_EQUAL_TEXT(3, monitor.code, monitor.output.c_str());
    CHECK_TEXT(Has(monitor, "busy: another host holds the board"), monitor.output.c_str());
    CHECK_TEXT(took < 2.0, std::to_string(took).c_str());  // was 3 s, then "no answer to Hello"
    LONGS_EQUAL_TEXT(0, hold.Stop(signal), strsignal(signal));
    LONGS_EQUAL_TEXT(0, t.Faults(), strsignal(signal));  // at once: not busy, no fault
  }
  // A command that is not waiting is cut short by the signal, its session closed all the same.
  Background monitor(t.address(), {"monitor", "--duration", "8"});
  CHECK_TEXT(monitor.WaitFor("line"), monitor.output().c_str());
  LONGS_EQUAL(0, monitor.Stop(SIGTERM));
  LONGS_EQUAL(0, t.Faults());
}

/// A host killed with fingers actuated cannot close: host_silence latches, and the refusal the
/// next command gets says which fault, when, and what to do.
void KilledHost(const Target& t) {
  {
    Background hold(t.address(), {"line", "1=30", "--hold", "8"});
    CHECK_TEXT(hold.WaitFor("holding for 8 s"), hold.output().c_str());
    LONGS_EQUAL(128 + SIGKILL, hold.Stop(SIGKILL));
  }
  Pause(kPauseMs);
  LONGS_EQUAL(kHostSilence, t.FaultsBecome(kHostSilence));
  const Run refused = t.Palpa("set 1=L2");
  LONGS_EQUAL_TEXT(1, refused.code, refused.output.c_str());
  CHECK_TEXT(Has(refused, "faulted: host_silence, latched at board time"), refused.output.c_str());
  CHECK_TEXT(Has(refused, "went silent while it was actuated"), refused.output.c_str());
  CHECK_TEXT(Has(refused, "palpa clear"), refused.output.c_str());
  LONGS_EQUAL(0, t.Palpa("clear").code);
  LONGS_EQUAL(0, t.Palpa("set 1=L2").code);
  LONGS_EQUAL(0, t.Faults());
}

void ProgramsCloseAndReopen(const Target& t) {
  const Run c = Shell(std::string(PALPA_CLOSE_REOPEN) + " " + t.address());
  LONGS_EQUAL_TEXT(0, c.code, c.output.c_str());
  const Run python = Shell("PALPA_LIBRARY=" + std::string(PALPA_LIBRARY) + " /usr/bin/python3 " +
                           PALPA_CLOSE_REOPEN_PY + " " + t.address());
  LONGS_EQUAL_TEXT(0, python.code, python.output.c_str());
}

/// A raw host on the line: a session with line 1 at 30 kPa, fresh heartbeats for 300 ms.
void Actuate(MiniClient& client, const std::string& address, uint32_t nonce) {
  const size_t colon = address.rfind(':');
  CHECK(client.ConnectTcp("127.0.0.1", std::atoi(address.c_str() + colon + 1)));
  CHECK(client.Hello(nonce).ok());
  LONGS_EQUAL((int)pp::Status::kOk, (int)client.Reliable(pp::ClearFault{}));
  LONGS_EQUAL((int)pp::Status::kOk, (int)client.RawSetpoint(0, 0, 30000));
  for (uint32_t g = 1; g <= 15; ++g) {
    client.Send(pp::Heartbeat{0, g});
    client.Read(20);
  }
}

/// Runs `frame_every_20ms` for up to 3 s (thirty timeouts of real time; a board behind real time
/// needs more of it) while reading telemetry; true once a frame showed host_silence with line 1
/// safe in its last tick (the session's end).
template <class F>
bool EndsDespite(MiniClient& reader, F&& frame_every_20ms) {
  for (int i = 0; i < 150; ++i) {
    frame_every_20ms(i);
    for (const ReceivedFrame& f : reader.Read(20)) {
      if (!f.Is<pp::Telemetry>()) continue;
      const auto tm = f.As<pp::Telemetry>();
      if ((tm.fault_bitmap & kHostSilence) != 0 &&
          (tm.samples[(tm.tick_count - 1) * tm.line_count].status & pp::line_status::kSafe) != 0)
        return true;
    }
  }
  return false;
}

void StaleForeignAndSecondHostFrames(const Target& t) {
  {  // The session's own heartbeat, repeated: stale after the first.
    MiniClient a;
    Actuate(a, t.address(), 0xA1);
    CHECK(EndsDespite(a, [&](int) { a.Send(pp::Heartbeat{0, 99}); }));
  }
  {  // Heartbeats, always newer, naming another session.
    MiniClient a;
    Actuate(a, t.address(), 0xA2);
    uint32_t g = 100;
    CHECK(EndsDespite(a, [&](int) { a.Send(pp::Heartbeat{0xB0B, ++g}); }));
  }
  {  // A second host on the line: told busy, its heartbeats and setpoints count for nothing.
    MiniClient a, b;
    Actuate(a, t.address(), 0xA3);
    const size_t colon = t.address().rfind(':');
    CHECK(b.ConnectTcp("127.0.0.1", std::atoi(t.address().c_str() + colon + 1)));
    b.Send(pp::Hello{0xB3, 0});
    bool busy = false;
    for (const ReceivedFrame& f : b.Read(200)) {
      busy |= f.Is<pp::Nack>() && f.As<pp::Nack>().status == pp::Status::kBusy &&
              f.As<pp::Nack>().refused_type == static_cast<uint8_t>(pp::MessageType::kHello);
    }
    CHECK(busy);
    uint32_t g = 0;
    CHECK(EndsDespite(a, [&](int i) {
      b.Send(pp::Heartbeat{0xB3, ++g});
      pp::SetLineSetpoints sp{};
      sp.session = 0xB3;
      sp.generation = 100 + static_cast<uint32_t>(i);
      sp.entry_count = 1;
      sp.entries[0] = {0, 60000};
      b.Send(sp);
    }));
  }
  LONGS_EQUAL(kHostSilence, t.FaultsBecome(kHostSilence));
  LONGS_EQUAL(0, t.Palpa("clear").code);
}

}  // namespace

TEST_GROUP(SimSessions) {
  std::unique_ptr<Target> t;
  void setup() override { t = std::make_unique<SimTarget>(); }
  void teardown() override { t.reset(); }
};

TEST(SimSessions, CommandsInSequenceLeaveNoFault) { CommandsInSequence(*t); }
TEST(SimSessions, ASecondCommandIsBusyAndEverySignalCloses) { BusyAndSignals(*t); }
TEST(SimSessions, AKilledHostLatchesHostSilenceAndTheRefusalSaysWhy) { KilledHost(*t); }
TEST(SimSessions, ACProgramAndAPythonScriptCloseAndReopen) { ProgramsCloseAndReopen(*t); }
TEST(SimSessions, StaleForeignAndSecondHostFramesKeepNothingActuated) {
  StaleForeignAndSecondHostFrames(*t);
}

/// A command that does not poll for signals (flash) is cut short by one; its session is closed all
/// the same. With a host-silence timeout of 10 s, a session left to end by silence would keep the
/// board busy for the next command: it is not, so the Close was sent.
TEST(SimSessions, AFlashStoppedBySignalLeavesTheBoardSafeAndResumable) {
  Run r = t->Palpa("config set board.host_timeout_us=10000000");
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  char pattern[] = "/tmp/palpa-session-flash-XXXXXX";
  const std::string dir = mkdtemp(pattern);
  Shell("head -c 150000 /dev/urandom > " + dir + "/a.bin; cp " + dir + "/a.bin " + dir + "/b.bin");
  const std::string package = dir + "/new.palpa";
  r = Shell(std::string(PALPA_CLI_PATH) + " package " + dir + "/a.bin " + dir +
            "/b.bin --version 0.3.0 --counter 2 --sign " PALPA_DEVELOPMENT_KEY " --out " + package);
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  {  // Over a line that carries 5 kB/s (a 57 600 baud UART): the write takes seconds and the
     // signal lands within them, its Close queued behind up to the board's 4 KiB buffer (0.8 s).
    palpa::testing::SharedLine slow;
    CHECK(slow.Start(t->address(), 5000));
    Background flash(slow.address(), {"flash", package});
    CHECK_TEXT(flash.WaitFor(" bytes "), flash.output().c_str());  // writing
    Pause(300);                                                    // a full window in flight
    LONGS_EQUAL(128 + SIGTERM, flash.Stop(SIGTERM));
    CHECK_TEXT(flash.output().find("the session is closed, the board's outputs are safe") !=
                   std::string::npos,
               flash.output().c_str());
  }
  LONGS_EQUAL(0, t->Faults());  // at once (not busy for 10 s): the session closed, no fault
  r = t->Palpa("set 1=L2");     // update mode ended with the session
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  r = t->Palpa("flash " + package + " --resume");
  LONGS_EQUAL_TEXT(0, r.code, r.output.c_str());
  CHECK_TEXT(Has(r, "(resumed at "), r.output.c_str());
  CHECK(Has(r, "updated 0.1.0 → 0.3.0 (slot 1), confirmed"));
  Shell("rm -rf " + dir);
}

TEST_GROUP(QemuSessions) {
  std::unique_ptr<Target> t;
  void setup() override { t = std::make_unique<QemuTarget>(); }
  void teardown() override { t.reset(); }
};

TEST(QemuSessions, CommandsInSequenceLeaveNoFault) { CommandsInSequence(*t); }
TEST(QemuSessions, ASecondCommandIsBusyAndEverySignalCloses) { BusyAndSignals(*t); }
TEST(QemuSessions, AKilledHostLatchesHostSilenceAndTheRefusalSaysWhy) { KilledHost(*t); }
TEST(QemuSessions, ACProgramAndAPythonScriptCloseAndReopen) { ProgramsCloseAndReopen(*t); }
TEST(QemuSessions, StaleForeignAndSecondHostFramesKeepNothingActuated) {
  StaleForeignAndSecondHostFrames(*t);
}
