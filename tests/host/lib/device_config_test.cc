// The host library's configuration and packaging flows: a board's whole configuration read back
// from palpa-sim, checked and encoded as the firmware would (refusals name the section, nothing
// sent), applied staged; slot images laid out for the board kind's flash; simulator
// configurations known by name.
#include <string>
#include <vector>

#include "development_signer.h"
#include "palpa/host/device.h"
#include "palpa/host/device_uri.h"
#include "palpa/host/firmware_image.h"

// Last: its memory-leak macros redefine new.
#include "CppUTest/TestHarness.h"

namespace ph = palpa::host;
namespace pp = palpa::protocol;

TEST_GROUP(DeviceConfig){};

TEST(DeviceConfig, TheWholeConfigurationReadsBackIsCheckedAsTheBoardWouldAndAppliesStaged) {
  ph::DeviceOptions options;
  options.number_from = 1;
  auto opened = ph::Device::Open("sim:thesis-5finger", options);
  CHECK_TEXT(opened.ok(), opened.message.c_str());
  ph::Device& d = *opened.value;
  auto config = d.ReadConfig();
  CHECK_TEXT(config.ok(), config.message.c_str());
  LONGS_EQUAL(d.info().line_count, config.value.line_count);
  LONGS_EQUAL(d.info().finger_count, config.value.finger_count);
  LONGS_EQUAL(100000, config.value.board.host_timeout_us);

  // A line whose limits are upside down: refused locally, naming it as the caller numbers it.
  ph::BoardConfig bad = config.value;
  std::swap(bad.lines[1].limit_min_pa, bad.lines[1].limit_max_pa);
  std::vector<uint8_t> records;
  ph::Outcome o = d.EncodeConfig(bad, &records);
  LONGS_EQUAL((int)pp::Status::kOutOfRange, (int)o.status);
  STRCMP_CONTAINS("line 2: ", o.message.c_str());
  STRCMP_CONTAINS("(nothing was sent)", o.message.c_str());
  LONGS_EQUAL((int)pp::Status::kOutOfRange, (int)d.ApplyConfig(bad).status);

  ph::BoardConfig changed = config.value;
  changed.board.host_timeout_us = 150000;
  o = d.ApplyConfig(changed);
  CHECK_TEXT(o.ok(), o.message.c_str());
  auto again = d.ReadConfig();
  CHECK_TEXT(again.ok(), again.message.c_str());
  LONGS_EQUAL(150000, again.value.board.host_timeout_us);
  // The refused configuration changed nothing on the board.
  LONGS_EQUAL(config.value.lines[1].limit_max_pa, again.value.lines[1].limit_max_pa);
}

TEST(DeviceConfig, SlotImagesAreLaidOutForTheBoardKindsFlash) {
  ph::ImageSpec spec;
  spec.board_kind = pp::BoardKind::kMps2An386;
  spec.body.assign(1024, 0xA5);
  spec.signer = &palpa::testing::DevelopmentSigner();
  pp::ImageError why = pp::ImageError::kNone;
  for (uint8_t slot = 0; slot < 2; ++slot) {
    const auto image = ph::BuildSlotImage(spec, slot);
    CHECK_TEXT(image.ok(), image.message.c_str());
    pp::ImageInfo info{};
    LONGS_EQUAL((int)pp::Status::kOk, (int)ph::VerifyImageBytes(image.value, &info, &why));
    LONGS_EQUAL(256, info.header_size);  // an MCU's vector table is aligned after it
    LONGS_EQUAL(slot, info.slot);
  }
  spec.board_kind = pp::BoardKind::kSim;
  const auto sim = ph::BuildSlotImage(spec, 0);
  CHECK(sim.ok());
  pp::ImageInfo info{};
  LONGS_EQUAL((int)pp::Status::kOk, (int)ph::VerifyImageBytes(sim.value, &info, &why));
  LONGS_EQUAL(pp::kImageHeaderSize, info.header_size);

  spec.body.assign(16 * 1024 * 1024, 0);
  const auto too_large = ph::BuildSlotImage(spec, 1);
  LONGS_EQUAL((int)pp::Status::kOutOfRange, (int)too_large.status);
  STRCMP_CONTAINS("16777216 bytes do not fit a slot of ", too_large.message.c_str());
}

TEST(DeviceConfig, SimulatorConfigurationsAreKnownByName) {
  STRCMP_EQUAL("", ph::SimConfigError("thesis-5finger").c_str());
  const std::string why = ph::SimConfigError("thesis-6finger");
  STRCMP_CONTAINS("unknown configuration (", why.c_str());
  STRCMP_CONTAINS("thesis-5finger", why.c_str());
  STRCMP_CONTAINS("full-8", why.c_str());
}
