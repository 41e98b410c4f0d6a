// Runs inside the guest (tests/kernel/gpio): hal/linux's GPIO classes on gpio-mockup lines, whose
// levels debugfs shows and drives, and WatchdogDevice on QEMU's i6300esb.
//   palpa_guest_gpio_tests [CppUTest options]   the suite (the chip from PALPA_GPIO_CHIP)
//   palpa_guest_gpio_tests unclean-close        arms the watchdog and exits without the magic close
//   palpa_guest_gpio_tests after-reset          passes when the driver reports a watchdog reset
#include <time.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>

#include "CppUTest/CommandLineTestRunner.h"
#include "CppUTest/TestHarness.h"
#include "palpa/hal/linux/gpio_edge_input.h"
#include "palpa/hal/linux/gpio_output.h"
#include "palpa/hal/linux/watchdog_device.h"

using palpa::hal::linux_gpio::GpioEdge;
using palpa::hal::linux_gpio::GpioEdgeInput;
using palpa::hal::linux_gpio::GpioOutput;
using palpa::hal::linux_wdt::WatchdogDevice;

namespace {

constexpr const char* kWatchdog = "/dev/watchdog";

std::string Chip() {
  const char* chip = std::getenv("PALPA_GPIO_CHIP");
  return chip != nullptr ? chip : "gpiochip0";
}

std::string Spec(int line) { return Chip() + ":" + std::to_string(line); }

// gpio-mockup's debugfs file of a line: reads its level, a write sets its pull (an input follows).
std::string DebugfsPath(int line) {
  return "/sys/kernel/debug/gpio-mockup/" + Chip() + "/" + std::to_string(line);
}

int ReadLevel(int line) {
  std::ifstream in(DebugfsPath(line));
  int level = -1;
  in >> level;
  return level;
}

void Pull(int line, int level) {
  std::ofstream out(DebugfsPath(line));
  out << level;
  out.close();
  CHECK_TEXT(!out.fail(), ("cannot write " + DebugfsPath(line)).c_str());
}

int64_t NowNs() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<int64_t>(ts.tv_sec) * 1000000000 + ts.tv_nsec;
}

void SleepMs(int ms) { usleep(static_cast<useconds_t>(ms) * 1000); }

bool Contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

}  // namespace

TEST_GROUP(GuestGpioOutput){};

TEST(GuestGpioOutput, TheLineStartsAtItsInitialValueAndFollowsSet) {
  auto opened_high = GpioOutput::Open(Spec(0), true);
  CHECK_TEXT(opened_high.ok(), opened_high.message.c_str());
  auto opened_low = GpioOutput::Open(Spec(1), false);
  CHECK_TEXT(opened_low.ok(), opened_low.message.c_str());
  auto& high = opened_high.value;
  auto& low = opened_low.value;
  LONGS_EQUAL(1, ReadLevel(0));
  LONGS_EQUAL(0, ReadLevel(1));
  CHECK(high->Set(false) == palpa::hal::Status::kOk);
  CHECK(low->Set(true) == palpa::hal::Status::kOk);
  LONGS_EQUAL(0, ReadLevel(0));
  LONGS_EQUAL(1, ReadLevel(1));
  CHECK(high->Set(true) == palpa::hal::Status::kOk);
  LONGS_EQUAL(1, ReadLevel(0));
}

TEST(GuestGpioOutput, AMissingChipOrLineOrABusyLineIsRefusedByName) {
  std::string error = GpioOutput::Open("nochip:0", false).message;
  CHECK_TEXT(Contains(error, "'nochip:0': no GPIO chip 'nochip'"), error.c_str());
  error = GpioOutput::Open(Spec(8), false).message;
  CHECK_TEXT(Contains(error, "chip " + Chip() + " has no line 8"), error.c_str());
  error = GpioOutput::Open(Chip() + ":x", false).message;
  CHECK_TEXT(Contains(error, "line 'x' is not a line number"), error.c_str());
  auto held = GpioOutput::Open(Spec(2), false);
  CHECK_TEXT(held.ok(), held.message.c_str());
  auto busy = GpioOutput::Open(Spec(2), true);
  POINTERS_EQUAL(nullptr, busy.value.get());
  error = busy.message;
  CHECK_TEXT(Contains(error, "'" + Spec(2) + "': cannot drive the line (Device or resource busy"),
             error.c_str());
  LONGS_EQUAL(0, ReadLevel(2));  // the refused request changed nothing
  const auto watched = GpioEdgeInput::Open(Spec(2), false);
  POINTERS_EQUAL(nullptr, watched.value.get());
  error = watched.message;
  CHECK_TEXT(Contains(error, "cannot watch the line's edges (Device or resource busy"),
             error.c_str());
}

TEST_GROUP(GuestGpioEdgeInput){};

TEST(GuestGpioEdgeInput, TheLevelFollowsThePullActiveHighOrActiveLow) {
  Pull(3, 0);
  Pull(4, 0);
  auto high_opened = GpioEdgeInput::Open(Spec(3), false);
  CHECK_TEXT(high_opened.ok(), high_opened.message.c_str());
  auto high = std::move(high_opened.value);
  auto low_opened = GpioEdgeInput::Open(Spec(4), true);
  CHECK_TEXT(low_opened.ok(), low_opened.message.c_str());
  auto low = std::move(low_opened.value);
  CHECK_FALSE(high->active());
  CHECK_TRUE(low->active());  // an active-low E-stop with its contact open is pressed
  Pull(3, 1);
  Pull(4, 1);
  CHECK_TRUE(high->active());
  CHECK_FALSE(low->active());
  GpioEdge edges[4];
  LONGS_EQUAL(1, high->ReadEvents(edges, 4));
  CHECK_TRUE(edges[0].active);
  // The HAL's DigitalInput, after the edges were taken (Read drains the same queue): the level.
  CHECK_TRUE(high->Read());
  LONGS_EQUAL(1, low->ReadEvents(edges, 4));
  CHECK_FALSE(edges[0].active);  // released: reported in the line's own sense, not as high
  Pull(4, 0);
  SleepMs(20);
  LONGS_EQUAL(1, low->ReadEvents(edges, 4));
  CHECK_TRUE(edges[0].active);
}

TEST(GuestGpioEdgeInput, EdgesComeInOrderWithTheirTimesAndNoneIsLostAcrossReads) {
  Pull(5, 0);
  auto input_opened = GpioEdgeInput::Open(Spec(5), true);
  CHECK_TEXT(input_opened.ok(), input_opened.message.c_str());
  auto input = std::move(input_opened.value);
  GpioEdge edges[8];
  LONGS_EQUAL(0, input->ReadEvents(edges, 8));  // nothing queued: returns at once
  // Six edges, each given time to be handled: the kernel's v1 line events take their direction
  // from the level when the event is handled, so edges closer than that are not what is tested.
  constexpr int kEdges = 6;
  int64_t before[kEdges], after[kEdges];
  for (int i = 0; i < kEdges; ++i) {
    before[i] = NowNs();
    Pull(5, i % 2 == 0 ? 1 : 0);
    SleepMs(20);
    after[i] = NowNs();
  }
  // Read in two parts: the four first, then what stayed queued.
  LONGS_EQUAL(4, input->ReadEvents(edges, 4));
  LONGS_EQUAL(2, input->ReadEvents(edges + 4, 4));
  LONGS_EQUAL(0, input->ReadEvents(edges, 8));
  for (int i = 0; i < kEdges; ++i) {
    // Active low: a rising pull releases the line, a falling one asserts it.
    CHECK_EQUAL_TEXT(i % 2 != 0, edges[i].active, ("edge " + std::to_string(i)).c_str());
    CHECK_TEXT(edges[i].timestamp_ns >= before[i] && edges[i].timestamp_ns <= after[i],
               ("edge " + std::to_string(i) + " stamped outside the time it was made").c_str());
  }
  CHECK_TRUE(input->active());
}

TEST_GROUP(GuestWatchdog){};

TEST(GuestWatchdog, TheTimeoutIsSetAndReadBackAndABadOneRefused) {
  std::string error;
  auto dog_opened = WatchdogDevice::Open(kWatchdog, 2);
  CHECK_TEXT(dog_opened.ok(), dog_opened.message.c_str());
  auto dog = std::move(dog_opened.value);
  LONGS_EQUAL(2, dog->timeout_s());
  CHECK_FALSE(dog->reset_by_watchdog());  // this boot was not a watchdog's reset
  CHECK_TEXT(dog->Kick(), dog->error().c_str());
  CHECK_TEXT(dog->Close(), dog->error().c_str());
  auto refused = WatchdogDevice::Open(kWatchdog, 3000);
  POINTERS_EQUAL(nullptr, refused.value.get());
  error = refused.message;
  CHECK_TEXT(Contains(error, "/dev/watchdog: the driver refuses a timeout of 3000 s"),
             error.c_str());
  refused = WatchdogDevice::Open(kWatchdog, -1);
  POINTERS_EQUAL(nullptr, refused.value.get());
  error = refused.message;
  CHECK_TEXT(Contains(error, "timeout -1 s (0: the driver's own)"), error.c_str());
  dog_opened = WatchdogDevice::Open(kWatchdog, 0);  // the driver's own: 2 s, set above
  CHECK_TEXT(dog_opened.ok(), dog_opened.message.c_str());
  dog = std::move(dog_opened.value);
  LONGS_EQUAL(2, dog->timeout_s());
  CHECK_TEXT(dog->Close(), dog->error().c_str());
  refused = WatchdogDevice::Open("/dev/nowatchdog", 1);
  POINTERS_EQUAL(nullptr, refused.value.get());
  error = refused.message;
  CHECK_TEXT(Contains(error, "/dev/nowatchdog: cannot open the watchdog"), error.c_str());
}

// A reset here ends the guest's first boot early; the next boot finds the phase marker at "tests"
// and fails the scenario.
TEST(GuestWatchdog, KicksKeepTheMachineUpAndTheMagicCloseStopsTheWatchdog) {
  auto dog_opened = WatchdogDevice::Open(kWatchdog, 1);
  CHECK_TEXT(dog_opened.ok(), dog_opened.message.c_str());
  auto dog = std::move(dog_opened.value);
  for (int i = 0; i < 25; ++i) {  // 5 s of kicks: unkicked, the i6300esb resets in about 1 s
    CHECK_TEXT(dog->Kick(), dog->error().c_str());
    SleepMs(200);
  }
  CHECK_TEXT(dog->Close(), dog->error().c_str());
  SleepMs(5000);  // stopped: no reset
  CHECK_FALSE(dog->Kick());
}

int main(int argc, char** argv) {
  if (argc == 2 && std::strcmp(argv[1], "unclean-close") == 0) {
    auto opened = WatchdogDevice::Open(kWatchdog, 1);
    auto& dog = opened.value;
    if (dog == nullptr || !dog->Kick()) {
      std::fprintf(stderr, "unclean-close: %s\n",
                   dog ? dog->error().c_str() : opened.message.c_str());
      return 1;
    }
    std::printf("unclean-close: armed for %d s, exiting without the magic close\n",
                dog->timeout_s());
    return 0;  // the destructor closes without 'V'
  }
  if (argc == 2 && std::strcmp(argv[1], "after-reset") == 0) {
    auto opened = WatchdogDevice::Open(kWatchdog, 1);
    auto& dog = opened.value;
    if (dog == nullptr) {
      std::fprintf(stderr, "after-reset: %s\n", opened.message.c_str());
      return 1;
    }
    const bool reset = dog->reset_by_watchdog();
    if (!dog->Close()) std::fprintf(stderr, "after-reset: %s\n", dog->error().c_str());
    std::printf("after-reset: the driver %s a watchdog reset\n",
                reset ? "reports" : "does not report");
    return reset ? 0 : 1;
  }
  return CommandLineTestRunner::RunAllTests(argc, argv);
}
