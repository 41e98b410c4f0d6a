// Firmware update against the simulated NOR flash: images checked byte for byte, boot-state
// records that survive torn writes, a full update, resume, refusals, revert of an unconfirmed
// trial, recovery, and a hundred power cuts after each of which a valid image boots.
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <random>
#include <string>

#include "development_signer.h"
#include "update_scenario.h"

#include "CppUTest/TestHarness.h"

namespace core = palpa::core;
namespace pp = palpa::protocol;
namespace pt = palpa::testing;
namespace ph = palpa::host;

TEST_GROUP(FirmwareImage){};

TEST(FirmwareImage, ABuiltImageVerifiesAndAnyCorruptedByteIsRefused) {
  const ph::UpdatePackage release = pt::MakeRelease(2, 3, 7, 3000, 1);
  const std::vector<uint8_t>& image = release.slot_image[1];
  pp::ImageInfo info;
  pp::ImageError error;
  LONGS_EQUAL((int)pp::Status::kOk, (int)ph::VerifyImageBytes(image, &info, &error));
  LONGS_EQUAL(2, info.version_major);
  LONGS_EQUAL(3, info.version_minor);
  LONGS_EQUAL(7, info.rollback_counter);
  LONGS_EQUAL(1, info.slot);
  LONGS_EQUAL(image.size(), info.total_size);
  std::mt19937 rng(5);
  for (int k = 0; k < 300; ++k) {
    std::vector<uint8_t> bad = image;
    const size_t at = rng() % bad.size();
    bad[at] ^= static_cast<uint8_t>(1u << (rng() % 8));
    CHECK_TEXT(ph::VerifyImageBytes(bad, &info, &error) != pp::Status::kOk,
               ("a flipped bit at " + std::to_string(at) + " went unnoticed").c_str());
  }
  std::vector<uint8_t> truncated(image.begin(), image.end() - 10);
  CHECK(ph::VerifyImageBytes(truncated, &info, &error) != pp::Status::kOk);
}

TEST(FirmwareImage, APaddedHeaderPutsTheBodyOnItsBoundaryAndTheHashCoversThePadding) {
  ph::ImageSpec spec;
  spec.body = {1, 2, 3, 4, 5, 6, 7, 8};
  spec.header_size = 256;  // a Cortex-M vector table after it is 256-byte aligned
  spec.board_kind = pp::BoardKind::kMps2An386;
  spec.signer = &pt::DevelopmentSigner();
  std::vector<uint8_t> image = ph::BuildImage(spec);
  pp::ImageInfo info;
  pp::ImageError error;
  LONGS_EQUAL((int)pp::Status::kOk, (int)ph::VerifyImageBytes(image, &info, &error));
  LONGS_EQUAL(256, info.header_size);
  LONGS_EQUAL(1, image[256]);
  image[100] = 0x55;  // inside the padding
  CHECK(ph::VerifyImageBytes(image, &info, &error) != pp::Status::kOk);
  LONGS_EQUAL((int)pp::ImageError::kHashMismatch, (int)error);
  spec.header_size = 30;  // not a header this format has
  CHECK(ph::VerifyImageBytes(ph::BuildImage(spec), &info, &error) != pp::Status::kOk);
}

TEST(FirmwareImage, Sha256MatchesTheSystemsSha256sum) {
  std::mt19937 rng(9);
  for (size_t size : {0ul, 55ul, 56ul, 64ul, 1000ul, 65537ul}) {
    std::vector<uint8_t> data(size);
    for (uint8_t& b : data) b = static_cast<uint8_t>(rng());
    // A file of its own: two test runs at once must not hash each other's data.
    std::string path = (std::filesystem::temp_directory_path() / "palpa-sha-XXXXXX").string();
    const int fd = mkstemp(path.data());
    CHECK(fd >= 0);
    CHECK(data.empty() || write(fd, data.data(), data.size()) == static_cast<ssize_t>(data.size()));
    close(fd);
    FILE* p = popen(("sha256sum " + path).c_str(), "r");
    char expected[65] = {};
    CHECK(std::fread(expected, 1, 64, p) == 64);
    pclose(p);
    std::filesystem::remove(path);
    const pp::Sha256Digest d = pp::Sha256Of(data.data(), data.size());
    char got[65] = {};
    for (int i = 0; i < 32; ++i) std::snprintf(got + 2 * i, 3, "%02x", d[static_cast<size_t>(i)]);
    STRCMP_EQUAL(expected, got);
  }
}

TEST(FirmwareImage, PackagesRefuseWhatIsNotOneRelease) {
  const ph::UpdatePackage a = pt::MakeRelease(1, 1, 2, 2000, 1);
  const ph::UpdatePackage b = pt::MakeRelease(1, 2, 2, 2000, 1);
  CHECK(ph::ReadPackage(ph::WritePackage(a)).ok());
  std::vector<uint8_t> bytes = ph::WritePackage(a);
  bytes.resize(bytes.size() - 100);
  auto read = ph::ReadPackage(bytes);
  LONGS_EQUAL((int)pp::Status::kImageInvalid, (int)read.status);
  CHECK(read.message.find("truncated") != std::string::npos);
  ph::UpdatePackage mixed = a;
  mixed.slot_image[1] = b.slot_image[1];
  read = ph::ReadPackage(ph::WritePackage(mixed));
  CHECK_FALSE(read.ok());
  CHECK(read.message.find("not one release") != std::string::npos);
  ph::UpdatePackage swapped = a;
  std::swap(swapped.slot_image[0], swapped.slot_image[1]);
  read = ph::ReadPackage(ph::WritePackage(swapped));
  CHECK_FALSE(read.ok());
  CHECK(read.message.find("linked for slot") != std::string::npos);
  bytes = ph::WritePackage(a);
  bytes[300] ^= 0x10;
  read = ph::ReadPackage(bytes);
  CHECK_FALSE(read.ok());
  CHECK(read.message.find("SHA-256") != std::string::npos);
}

TEST_GROUP(BootState){};

TEST(BootState, RecordsAlternateSectorsAndATornOneIsIgnored) {
  palpa::hal::fake::SimulatedNorFlash flash(core::kDefaultLayout.total,
                                            core::kDefaultLayout.sector_size, 3);
  core::BootStore store(&flash, core::kDefaultLayout);
  LONGS_EQUAL(0, store.Load().sequence);
  core::BootState s;
  for (uint32_t i = 1; i <= 600; ++i) {  // 256 records per sector: alternates twice
    s.rollback_floor = i;
    LONGS_EQUAL((int)pp::Status::kOk, (int)store.Save(s));
  }
  core::BootStore again(&flash, core::kDefaultLayout);
  LONGS_EQUAL(600, again.Load().rollback_floor);
  // The next records are torn: early (its fields half there) and late (all but its CRC).
  for (uint32_t cut : {10u, 24u}) {
    flash.CutPowerAfter(cut);
    s.rollback_floor = 601;
    CHECK(core::BootStore(&flash, core::kDefaultLayout).Save(s) != pp::Status::kOk);
    flash.PowerOn();
  }
  core::BootStore after(&flash, core::kDefaultLayout);
  LONGS_EQUAL(600, after.Load().rollback_floor);
  s.rollback_floor = 602;
  LONGS_EQUAL((int)pp::Status::kOk, (int)after.Save(s));  // written past the torn record
  LONGS_EQUAL(602, core::BootStore(&flash, core::kDefaultLayout).Load().rollback_floor);
}

TEST(BootState, NewestReadsFlashOnceAndFollowsSaves) {
  palpa::hal::fake::SimulatedNorFlash flash(core::kDefaultLayout.total,
                                            core::kDefaultLayout.sector_size, 4);
  core::BootState s;
  s.rollback_floor = 3;
  LONGS_EQUAL((int)pp::Status::kOk, (int)core::BootStore(&flash, core::kDefaultLayout).Save(s));
  core::BootStore store(&flash, core::kDefaultLayout);
  LONGS_EQUAL(3, store.Newest().rollback_floor);  // the first call loads
  s.rollback_floor = 5;
  LONGS_EQUAL((int)pp::Status::kOk, (int)store.Save(s));
  LONGS_EQUAL(5, store.Newest().rollback_floor);  // a save is followed
  // Flash changed behind the store's back (only a new boot does that): no longer read.
  for (uint32_t offset : core::kDefaultLayout.state_offset) flash.Erase(offset);
  LONGS_EQUAL(5, store.Newest().rollback_floor);
  LONGS_EQUAL(0, store.Load().rollback_floor);
}

TEST_GROUP(FirmwareUpdate){};

TEST(FirmwareUpdate, AFullUpdateBootsTheNewImageConfirmed) {
  pt::UpdateWorld w(1);
  LONGS_EQUAL(0, w.running);
  CHECK(w.last_boot.reason == core::BootReason::kFirstBoot);
  const pt::UpdateOutcome u = pt::RunUpdate(w, pt::MakeRelease(1, 1, 2, 40 * 1024, 2));
  CHECK_TEXT(u.completed, u.failed_step.c_str());
  LONGS_EQUAL(1, w.running);
  const core::BootDecision d = w.Reboot();
  CHECK(d.reason == core::BootReason::kConfirmed);
  LONGS_EQUAL(1, d.slot);
  core::UpdateEngine engine(&w.flash, w.layout, w.kind, w.running);
  const pp::SlotsReport r = engine.Slots();
  CHECK(r.slots[1].state == pp::SlotState::kConfirmed);
  LONGS_EQUAL(1, r.slots[1].version_minor);
  CHECK(r.slots[0].state == pp::SlotState::kValid);
  LONGS_EQUAL(2, engine.rollback_floor());
  // The next update goes to slot 0 again.
  CHECK(pt::RunUpdate(w, pt::MakeRelease(1, 2, 2, 30 * 1024, 3)).completed);
  LONGS_EQUAL(0, w.running);
}

TEST(FirmwareUpdate, ATrialThatIsNeverConfirmedRevertsOnTheNextReset) {
  pt::UpdateWorld w(2);
  CHECK(pt::RunUpdate(w, pt::MakeRelease(1, 1, 2, 20 * 1024, 4), false).completed);
  LONGS_EQUAL(1, w.running);                // the trial runs...
  const core::BootDecision d = w.Reboot();  // ...and the board resets before the host confirms
  CHECK(d.reason == core::BootReason::kReverted);
  LONGS_EQUAL(0, d.slot);
  CHECK(w.Reboot().reason == core::BootReason::kConfirmed);
  // The reverted image's counter never became the floor: the same release can be tried again.
  CHECK(pt::RunUpdate(w, pt::MakeRelease(1, 1, 2, 20 * 1024, 4)).completed);
}

TEST(FirmwareUpdate, AWriteResumesFromTheOffsetTheBoardReports) {
  pt::UpdateWorld w(3);
  const std::vector<uint8_t> image = pt::MakeRelease(1, 1, 2, 10 * 1024, 5).slot_image[1];
  core::UpdateEngine engine(&w.flash, w.layout, w.kind, w.running);
  const auto size = static_cast<uint32_t>(image.size());
  uint32_t detail = 0;
  LONGS_EQUAL((int)pp::Status::kOk, (int)engine.Enter({1, size}, &detail));
  LONGS_EQUAL((int)pp::Status::kOk, (int)engine.Erase({1, 0, 16 * 1024}, &detail));
  auto chunk = [&](uint32_t at) {
    pp::UpdateWrite m;
    m.slot = 1;
    m.offset = at;
    m.data_size = static_cast<uint8_t>(std::min<uint32_t>(200, size - at));
    std::copy(image.begin() + at, image.begin() + at + m.data_size, m.data.begin());
    return m;
  };
  for (uint32_t at = 0; at < 4000; at += 200)
    CHECK(engine.Write(chunk(at), &detail) == pp::Status::kOk);
  // The link drops; the host comes back, enters again and asks where to go on.
  LONGS_EQUAL((int)pp::Status::kOk, (int)engine.Enter({1, size}, &detail));
  const pp::UpdateStatus st = engine.Query(1);
  LONGS_EQUAL(4000, st.written_bytes);
  CHECK(st.written_sha256 == pp::Sha256Of(image.data(), 4000));
  LONGS_EQUAL((int)pp::Status::kOutOfRange, (int)engine.Write(chunk(4400), &detail));  // a gap
  LONGS_EQUAL(4000, detail);
  LONGS_EQUAL((int)pp::Status::kOk, (int)engine.Write(chunk(3800), &detail));  // a repeat: fine
  for (uint32_t at = 4000; at < size; at += 200)
    CHECK(engine.Write(chunk(at), &detail) == pp::Status::kOk);
  LONGS_EQUAL((int)pp::Status::kOk,
              (int)engine.Activate({1, size, pp::Sha256Of(image.data(), image.size())}, &detail));
  CHECK(w.Reboot().reason == core::BootReason::kTrial);
}

TEST(FirmwareUpdate, AnUpdateLeftByANewSessionStopsHoldingTheBoardAndResumesWhenEnteredAgain) {
  pt::UpdateWorld w(6);
  const std::vector<uint8_t> image = pt::MakeRelease(1, 1, 2, 10 * 1024, 6).slot_image[1];
  core::UpdateEngine engine(&w.flash, w.layout, w.kind, w.running);
  const auto size = static_cast<uint32_t>(image.size());
  uint32_t detail = 0;
  LONGS_EQUAL((int)pp::Status::kOk, (int)engine.Enter({1, size}, &detail));
  LONGS_EQUAL((int)pp::Status::kOk, (int)engine.Erase({1, 0, 16 * 1024}, &detail));
  pp::UpdateWrite first;
  first.slot = 1;
  first.data_size = 200;
  std::copy(image.begin(), image.begin() + 200, first.data.begin());
  LONGS_EQUAL((int)pp::Status::kOk, (int)engine.Write(first, &detail));
  // The host is gone; another opens a session: the board is no longer held in update mode.
  engine.LeaveUpdateMode();
  CHECK_FALSE(engine.in_update_mode());
  CHECK_FALSE(engine.Query(1).in_update_mode);
  LONGS_EQUAL((int)pp::Status::kWrongMode, (int)engine.Write(first, &detail));
  LONGS_EQUAL((int)pp::Status::kWrongMode,
              (int)engine.Activate({1, size, pp::Sha256Of(image.data(), size)}, &detail));
  LONGS_EQUAL(200, engine.Query(1).written_bytes);  // what is written stays...
  LONGS_EQUAL((int)pp::Status::kOk, (int)engine.Enter({1, size}, &detail));
  CHECK(engine.in_update_mode());
  LONGS_EQUAL(200, engine.Query(1).written_bytes);  // ...and the same image goes on from it
  CHECK(engine.Query(1).written_sha256 == pp::Sha256Of(image.data(), 200));
  engine.LeaveUpdateMode();
  LONGS_EQUAL((int)pp::Status::kOk, (int)engine.Enter({1, size - 4}, &detail));
  LONGS_EQUAL(0, engine.Query(1).written_bytes);  // another image starts from nothing
}

TEST(FirmwareUpdate, WrongKindCorruptedOlderAndRunningSlotImagesAreRefused) {
  pt::UpdateWorld w(4);
  CHECK(pt::RunUpdate(w, pt::MakeRelease(1, 1, 5, 8 * 1024, 6)).completed);  // floor now 5
  const uint8_t slot = 0;  // inactive: slot 1 runs
  auto attempt = [&](const std::vector<uint8_t>& image, uint32_t corrupt_at, uint32_t* detail) {
    core::UpdateEngine engine(&w.flash, w.layout, w.kind, w.running);
    const auto size = static_cast<uint32_t>(image.size());
    engine.Enter({slot, size}, detail);
    engine.Erase({slot, 0, 16 * 1024}, detail);
    for (uint32_t at = 0; at < size; at += 240) {
      pp::UpdateWrite m;
      m.slot = slot;
      m.offset = at;
      m.data_size = static_cast<uint8_t>(std::min<uint32_t>(240, size - at));
      std::copy(image.begin() + at, image.begin() + at + m.data_size, m.data.begin());
      if (corrupt_at >= at && corrupt_at < at + m.data_size) m.data[corrupt_at - at] ^= 0x40;
      engine.Write(m, detail);
    }
    return engine.Activate({slot, size, pp::Sha256Of(image.data(), image.size())}, detail);
  };
  uint32_t detail = 0;
  const auto other_board = pt::MakeRelease(1, 2, 5, 8 * 1024, 7, pp::BoardKind::kMps2An386);
  LONGS_EQUAL((int)pp::Status::kImageInvalid,
              (int)attempt(other_board.slot_image[0], ~0u, &detail));
  const auto good = pt::MakeRelease(1, 2, 5, 8 * 1024, 8);
  LONGS_EQUAL((int)pp::Status::kImageInvalid, (int)attempt(good.slot_image[0], 5000, &detail));
  const auto older = pt::MakeRelease(1, 3, 4, 8 * 1024, 9);
  LONGS_EQUAL((int)pp::Status::kRollbackRefused, (int)attempt(older.slot_image[0], ~0u, &detail));
  LONGS_EQUAL(5, detail);
  // Nothing refused was activated: the confirmed image still boots.
  CHECK(w.Reboot().reason == core::BootReason::kConfirmed);
  LONGS_EQUAL(1, w.running);
  core::UpdateEngine engine(&w.flash, w.layout, w.kind, w.running);
  LONGS_EQUAL((int)pp::Status::kOutOfRange, (int)engine.Enter({1, 1000}, &detail));  // running slot
}

namespace {

/// The engine's view of the flash, counting what it reads between two watchdog kicks.
class ReadCountingFlash final : public palpa::hal::Flash {
 public:
  explicit ReadCountingFlash(palpa::hal::Flash& flash) : flash_(flash) {}
  uint32_t since_kick = 0, worst = 0;

 private:
  pp::Status DoErase(uint32_t offset) override { return flash_.Erase(offset); }
  pp::Status DoProgram(uint32_t offset, const uint8_t* data, size_t size) override {
    return flash_.Program(offset, data, size);
  }
  pp::Status DoRead(uint32_t offset, uint8_t* out, size_t size) override {
    since_kick += static_cast<uint32_t>(size);
    worst = std::max(worst, since_kick);
    return flash_.Read(offset, out, size);
  }
  uint32_t DoSectorSize() const override { return flash_.sector_size(); }
  uint32_t DoSize() const override { return flash_.size(); }
  palpa::hal::Flash& flash_;
};

class ResettingWatchdog final : public palpa::hal::Watchdog {
 public:
  explicit ResettingWatchdog(ReadCountingFlash& flash) : flash_(flash) {}

 private:
  void DoStart(uint32_t) override {}
  void DoKick() override { flash_.since_kick = 0; }
  ReadCountingFlash& flash_;
};

}  // namespace

TEST(FirmwareUpdate, TheWatchdogIsKickedForEveryBlockAnImageCheckReads) {
  // Activation, confirmation and the slot report each hash a whole image: at the MPS2's 25 MHz
  // that takes longer than the application's 30 ms watchdog, which must not reset the board.
  pt::UpdateWorld w(11);
  ReadCountingFlash flash(w.flash);
  ResettingWatchdog watchdog(flash);
  const pt::UpdateOutcome u =
      pt::RunUpdate(w, pt::MakeRelease(1, 1, 2, 150 * 1024, 12), true, &watchdog, &flash);
  CHECK_TEXT(u.completed, u.failed_step.c_str());
  core::UpdateEngine engine(&flash, w.layout, w.kind, w.running, &watchdog);
  CHECK(engine.Slots().slots[1].state == pp::SlotState::kConfirmed);
  // The most read between two kicks is now two loads of the boot state (both record sectors
  // each, a compare per record: a few ms), a record read back and a hash block; without the
  // kicks it is a whole image's hash.
  const uint32_t record_scans = 2 * 2 * w.layout.sector_size;
  CHECK_TEXT(flash.worst <= record_scans + 256, std::to_string(flash.worst).c_str());
}

TEST(FirmwareUpdate, WithNoValidImageRecoveryModeTakesAnUpdate) {
  pt::UpdateWorld w(5);
  w.flash.Erase(w.layout.slot_offset[0]);  // the only image is gone
  core::BootDecision d = w.Reboot();
  CHECK(d.reason == core::BootReason::kRecovery);
  CHECK(d.slot == core::kNoSlot);
  CHECK(pt::RunUpdate(w, pt::MakeRelease(1, 1, 2, 8 * 1024, 10)).completed);
  d = w.Reboot();
  CHECK(d.reason == core::BootReason::kConfirmed);
  CHECK(d.slot <= 1);
}

TEST(FirmwareUpdate, AHundredPowerCutsEachLeaveABootableBoard) {
  const uint64_t total = pt::UpdateFlashBytes(1);
  std::mt19937 rng(11);
  std::map<std::string, int> phases;
  int old_image = 0, new_image = 0;
  for (int k = 0; k < 100; ++k) {
    // Seven in ten anywhere (mostly erase and write, where the bytes are); three in ten among
    // the last few hundred bytes, where the activate, trial-boot and confirm records are.
    const uint64_t cut = k < 70 ? rng() % (total + 200) : total - 150 + rng() % 300;
    const pt::CutOutcome o = pt::CutPowerDuringUpdate(cut, static_cast<uint32_t>(k + 1));
    CHECK_TEXT(o.valid, ("cut at byte " + std::to_string(cut) + " in " + o.phase +
                         ": no valid image booted (" + core::BootReasonName(o.reason) + ")")
                            .c_str());
    ++phases[o.phase];
    (o.is_new ? new_image : old_image)++;
  }
  for (const char* phase : {"erase", "write", "activate", "trial boot", "confirm", "after confirm"})
    CHECK_TEXT(phases.count(phase), phase);
  CHECK(old_image > 0 && new_image > 0);
}
