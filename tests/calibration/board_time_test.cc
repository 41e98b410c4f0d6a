// The rig's clock on a real-time board: waits count the board's time from its telemetry, so a
// simulator that falls behind (here: stopped, or crawling) does not cut a dwell short, and a board
// whose clock stops does not hold a wait forever.
#include <signal.h>

#include <atomic>
#include <chrono>
#include <string>
#include <thread>

#include "palpa/calibration/device_rig.h"
#include "palpa/host/device.h"
#include "sim_process.h"

#include "CppUTest/TestHarness.h"

namespace cal = palpa::calibration;
namespace ph = palpa::host;
namespace pt = palpa::testing;

namespace {

double Seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

/// Stops a process for `stop_ms` of real time, from a thread of its own.
class Pause {
 public:
  Pause(int pid, int stop_ms)
      : thread_([this, pid, stop_ms] {
          kill(pid, SIGSTOP);
          std::this_thread::sleep_for(std::chrono::milliseconds(stop_ms));
          continued_ = true;
          kill(pid, SIGCONT);
        }) {}
  ~Pause() { thread_.join(); }
  bool continued() const { return continued_; }

 private:
  std::atomic<bool> continued_{false};
  std::thread thread_;
};

}  // namespace

TEST_GROUP(BoardTime) {
  pt::SimProcess sim;
  std::unique_ptr<ph::Device> device;

  /// palpa-sim at 10x, a device on it, and a clock that has seen the board's telemetry.
  void Open() {
    CHECK(sim.Start(
        {"--config", "thesis-pneumatic-3", "--listen", "tcp:127.0.0.1:0", "--speed", "10"}));
    auto opened = ph::Device::Open(sim.address(), {});
    CHECK_TEXT(opened.ok(), opened.message.c_str());
    device = std::move(opened.value);
  }
  void teardown() override { device.reset(); }
};

TEST(BoardTime, AWaitLastsItsBoardTimeWhenTheSimulatorFallsBehind) {
  Open();
  cal::BoardTime time(*device);
  for (int i = 0; i < 100 && time.Now() == 0; ++i) time.Wait(0.01);
  CHECK(time.Now() > 0);
  const double before = time.Now();
  const auto started = std::chrono::steady_clock::now();
  {
    // 0.2 board seconds are 20 ms of real time at 10x; the simulator is stopped for 100 ms of it
    // and slips when it resumes, so counted in scaled real time the wait would end with the
    // board barely moved.
    Pause pause(sim.pid(), 100);
    time.Wait(0.2);
    CHECK(pause.continued());
  }
  CHECK(Seconds(started) >= 0.1);
  const double advanced = time.Now() - before;
  CHECK_TEXT(advanced >= 0.2, ("board time advanced " + std::to_string(advanced) + " s").c_str());
}

TEST(BoardTime, AWaitLastsItsBoardTimeWhileTheClockCrawlsForLongerThanASecond) {
  // A loaded machine: palpa-sim runs 10 ms in every 410 (stopped between), so its clock moves
  // in every second but slowly. 1 board second is 100 ms of real time at 10x and takes seconds
  // here; a wait bounded at its scaled time plus a second would end with the board short of it,
  // and a dwell would be cut.
  Open();
  cal::BoardTime time(*device);
  for (int i = 0; i < 100 && time.Now() == 0; ++i) time.Wait(0.01);
  const double before = time.Now();
  const auto started = std::chrono::steady_clock::now();
  std::atomic<bool> waited{false};
  std::thread crawl([&] {
    for (int i = 0; i < 100 && !waited; ++i) {
      kill(sim.pid(), SIGSTOP);
      std::this_thread::sleep_for(std::chrono::milliseconds(400));
      kill(sim.pid(), SIGCONT);
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  });
  time.Wait(1.0);
  waited = true;
  crawl.join();
  CHECK(Seconds(started) > 1.1);
  const double advanced = time.Now() - before;
  CHECK_TEXT(advanced >= 1.0, ("board time advanced " + std::to_string(advanced) + " s").c_str());
}

TEST(BoardTime, AWaitOnABoardWhoseClockStoppedEndsAfterASecondWithoutProgress) {
  Open();
  cal::BoardTime time(*device);
  for (int i = 0; i < 100 && time.Now() == 0; ++i) time.Wait(0.01);
  const double before = time.Now();
  Pause pause(sim.pid(), 3000);
  std::this_thread::sleep_for(std::chrono::milliseconds(20));  // its last frames are in
  const double stopped_at = time.Now();
  time.Wait(0.2);                  // 20 ms scaled; ends once a second passes with no progress
  CHECK_FALSE(pause.continued());  // returned while the board was still stopped
  CHECK(time.Now() - stopped_at < 0.2);
  CHECK(stopped_at >= before);
}
