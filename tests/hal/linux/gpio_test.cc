// GPIO lines through the libgpiod seam: specs parsed and refused with the reason, lines
// requested, driven and released; the reset and boot pin sequences of `palpa flash`.
#include <string>
#include <vector>

#include "fake_gpiod.h"
#include "palpa/hal/linux/gpio_edge_input.h"
#include "palpa/hal/linux/gpio_output.h"
#include "palpa/host/boot_pins.h"

#include "CppUTest/TestHarness.h"

namespace fg = palpa::testing::fake_gpiod;
using palpa::hal::linux_gpio::GpioOutput;

TEST_GROUP(Gpio){void setup() override{fg::Reset();
fg::state().chips = {"gpiochip0", "gpiochip1"};
}
void teardown() override { fg::Reset(); }  // the fake's log is freed inside the test
}
;

namespace {

/// Whether GpioOutput::Open refuses SPEC with `status` and a message that has `part`.
bool Refused(const std::string& spec, palpa::hal::Status status, const std::string& part) {
  auto opened = GpioOutput::Open(spec, false);
  return opened.status == status && opened.value == nullptr &&
         opened.message.find(part) != std::string::npos;
}

}  // namespace

TEST(Gpio, SpecsAreCheckedAndEveryFailureSaysWhy) {
  using palpa::hal::Status;
  CHECK(Refused("gpiochip0", Status::kBadValue, "'gpiochip0': expected CHIP:LINE"));
  CHECK(Refused("gpiochip0:x", Status::kBadValue, "line 'x' is not a line number"));
  CHECK(Refused("gpiochip7:3", Status::kNotFound, "no GPIO chip 'gpiochip7'"));
  CHECK(Refused("gpiochip0:40", Status::kNotFound, "has no line 40"));
  fg::state().busy = {"gpiochip1:4"};
  CHECK(Refused("gpiochip1:4", Status::kIoError, "another program"));
  LONGS_EQUAL(0, fg::state().open_chips);  // nothing left open after a failure
}

TEST(Gpio, ALineIsRequestedDrivenAndReleased) {
  {
    auto opened = GpioOutput::Open("1:5", true);  // a chip by number
    CHECK_TEXT(opened.ok(), opened.message.c_str());
    auto& line = opened.value;
    CHECK(line->Set(false) == palpa::hal::Status::kOk);
    // A value the kernel refuses is reported, not taken for written.
    fg::state().unwritable = {"gpiochip1:5"};
    CHECK(line->Set(true) == palpa::hal::Status::kIoError);
    fg::state().unwritable.clear();
    CHECK(line->Set(true) == palpa::hal::Status::kOk);
  }
  const std::vector<std::string> expected = {"request gpiochip1:5=1", "set gpiochip1:5=0",
                                             "failed set gpiochip1:5=1", "set gpiochip1:5=1",
                                             "release gpiochip1:5"};
  CHECK(fg::state().log == expected);
  LONGS_EQUAL(0, fg::state().open_chips);
}

TEST(Gpio, BootPinsHoldBootWhileResetPulsesAndReleaseItBeforeTheReboot) {
  auto reset = GpioOutput::Open("gpiochip0:1", true).value;
  auto boot = GpioOutput::Open("gpiochip0:2", false).value;
  std::vector<int> waits;
  palpa::host::BootPins pins(reset.get(), boot.get(), [&](int ms) { waits.push_back(ms); });
  pins.ResetIntoBootloader();
  pins.ReleaseBoot();
  pins.ResetIntoApplication();
  const std::vector<std::string> expected = {
      "request gpiochip0:1=1", "request gpiochip0:2=0",
      "set gpiochip0:2=1",                           // boot asserted before the reset...
      "set gpiochip0:1=0",     "set gpiochip0:1=1",  // ...pulsed
      "set gpiochip0:2=0",  // released before the reboot into the new image
      "set gpiochip0:2=0",     "set gpiochip0:1=0",     "set gpiochip0:1=1"};
  CHECK(fg::state().log == expected);
  CHECK(waits.size() == 4 && waits[0] == palpa::host::BootPins::kResetPulseMs);
}

TEST(Gpio, TheEStopSeesAPressShorterThanATickAndNeverBlocks) {
  using palpa::hal::linux_gpio::GpioEdgeInput;
  fg::state().busy = {"gpiochip0:9"};
  const auto busy = GpioEdgeInput::Open("gpiochip0:9", false);
  CHECK(busy.status == palpa::protocol::Status::kIoError && busy.value == nullptr);
  CHECK_TEXT(busy.message.find("'gpiochip0:9': cannot watch the line's edges") == 0,
             busy.message.c_str());
  auto opened = GpioEdgeInput::Open("gpiochip0:5", false);  // NC contact: high = pressed
  CHECK_TEXT(opened.ok(), opened.message.c_str());
  auto estop = std::move(opened.value);
  CHECK_TEXT(!estop->Read(), estop->error().c_str());  // nothing queued: the read did not wait
  // Pressed and released between two ticks: the level is back, the rising edge is not lost.
  fg::state().edges["gpiochip0:5"] = {true, false};
  CHECK(estop->Read());
  CHECK(!estop->Read());  // read once: the queue is drained
  // Shorter than the kernel's interrupt handling: both edges stamped with the level after them.
  fg::state().edges["gpiochip0:5"] = {false, false};
  CHECK(estop->Read());
  fg::state().edges["gpiochip0:5"] = {false};  // a release alone is no press
  CHECK(!estop->Read());
  fg::state().edges["gpiochip0:5"] = {true};  // the press alone, its release not yet handled
  CHECK(estop->Read());
  fg::state().edges["gpiochip0:5"] = {false};
  CHECK(!estop->Read());
  fg::state().levels["gpiochip0:5"] = 1;  // held down, its edge lost: the level says so
  CHECK(estop->Read());
  CHECK(estop->Read());
  fg::state().levels["gpiochip0:5"] = 0;
  CHECK(!estop->Read());
  CHECK(estop->error().empty());
  // A line that cannot be read is an asserted E-stop, from then on.
  fg::state().broken = {"gpiochip0:5"};
  CHECK(estop->Read());
  fg::state().broken.clear();
  CHECK(estop->Read());
  CHECK(estop->error().find("'gpiochip0:5': reading the line") != std::string::npos);

  // Active low: the kernel reports the line's sense, so a short pull to ground is an active edge.
  auto low_opened = GpioEdgeInput::Open("gpiochip1:2", true);
  CHECK_TEXT(low_opened.ok(), low_opened.message.c_str());
  auto low = std::move(low_opened.value);
  fg::state().levels["gpiochip1:2"] = 1;
  CHECK(!low->Read());
  fg::state().edges["gpiochip1:2"] = {false, true};
  CHECK(low->Read());
  CHECK(!low->Read());
}

TEST(Gpio, EdgesAreReadInOrderAndWhatDoesNotFitStaysQueued) {
  using palpa::hal::linux_gpio::GpioEdge;
  using palpa::hal::linux_gpio::GpioEdgeInput;
  auto input_opened = GpioEdgeInput::Open("gpiochip0:6", true);
  CHECK_TEXT(input_opened.ok(), input_opened.message.c_str());
  auto input = std::move(input_opened.value);
  fg::state().edges["gpiochip0:6"] = {false, true, false};  // pulled to ground, back, again
  GpioEdge edges[2];
  LONGS_EQUAL(2, input->ReadEvents(edges, 2));
  CHECK(edges[0].active && !edges[1].active);
  LONGS_EQUAL(1, input->ReadEvents(edges, 2));
  CHECK(edges[0].active);
  LONGS_EQUAL(0, input->ReadEvents(edges, 2));
  fg::state().broken = {"gpiochip0:6"};
  LONGS_EQUAL(-1, input->ReadEvents(edges, 2));
  CHECK(input->error().find("reading the line's edges failed") != std::string::npos);
}
