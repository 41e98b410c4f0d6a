// Flashing palpa-sim over its link: a full update seen answering Hello on the new image and
// confirmed, a dry run, refusals (kind, rollback, a corrupted package), and a write cut by a
// lost link that a second run resumes from what the board reports.
#include <atomic>
#include <random>
#include <string>

#include "mini_client.h"
#include "palpa/host/flasher.h"
#include "palpa/host/link.h"
#include "sim_process.h"
#include "update_scenario.h"

#include "CppUTest/TestHarness.h"

namespace ph = palpa::host;
namespace pp = palpa::protocol;
namespace pt = palpa::testing;

namespace {

/// A transport that goes dead after so many bytes written (a cable pulled mid-update). The link
/// reads on its own thread while the caller writes, so the cut is seen across threads.
class CutTransport final : public ph::Transport {
 public:
  CutTransport(std::unique_ptr<ph::Transport> inner, size_t budget)
      : inner_(std::move(inner)), budget_(budget) {}
  pp::Result<size_t> Read(uint8_t* out, size_t capacity, int timeout_ms) override {
    if (cut_) return ph::Status::kDisconnected;
    return inner_->Read(out, capacity, timeout_ms);
  }
  ph::Status Write(const uint8_t* data, size_t size) override {
    if (cut_ || size > budget_) {
      cut_ = true;
      return ph::Status::kDisconnected;
    }
    budget_ -= size;
    return inner_->Write(data, size);
  }
  std::string Describe() const override { return "cut " + inner_->Describe(); }

 private:
  std::unique_ptr<ph::Transport> inner_;
  size_t budget_;  // written by the writing thread only
  std::atomic<bool> cut_ = false;
};

std::unique_ptr<ph::Link> Connect(const std::string& address, size_t budget = SIZE_MAX) {
  auto t = ph::OpenTransport(address);
  CHECK_TEXT(t.ok(), t.message.c_str());
  std::unique_ptr<ph::Transport> transport = std::move(t.value);
  if (budget != SIZE_MAX) transport = std::make_unique<CutTransport>(std::move(transport), budget);
  ph::LinkOptions options;
  options.command_timeout_ms = 1000;
  auto link = ph::Link::Open(std::move(transport), options);
  CHECK_TEXT(link.ok(), link.message.c_str());
  return std::move(link.value);
}

/// Release 0.2.0 (counter 2) of the simulated board, 20 KiB.
ph::UpdatePackage Release(uint8_t minor, uint32_t counter,
                          pp::BoardKind kind = pp::BoardKind::kSim) {
  return pt::MakeRelease(0, minor, counter, 20 * 1024, minor, kind);
}

}  // namespace

TEST_GROUP(Flasher){};

TEST(Flasher, UpdatesConfirmsAndRefusesWhatItMust) {
  pt::SimProcess sim;
  CHECK(sim.Start({"--config", "thesis-pneumatic-3", "--listen", "tcp:127.0.0.1:0"}));
  auto link = Connect(sim.address());
  LONGS_EQUAL(0, link->board().active_slot);
  ph::FlashOptions dry;
  dry.dry_run = true;
  ph::FlashReport r = ph::FlashPackage(*link, Release(2, 2), dry);
  CHECK_TEXT(r.status == pp::Status::kOk, r.message.c_str());
  CHECK(r.message.find("would write 0.2.0") != std::string::npos);
  LONGS_EQUAL(0, link->board().active_slot);  // nothing changed

  int progress_calls = 0;
  ph::FlashOptions options;
  options.progress = [&](const ph::FlashProgress&) { ++progress_calls; };
  r = ph::FlashPackage(*link, Release(2, 2), options);
  CHECK_TEXT(r.status == pp::Status::kOk, r.message.c_str());
  CHECK(progress_calls > 50);
  const pp::HelloReply after = link->board();
  LONGS_EQUAL(1, after.active_slot);
  LONGS_EQUAL(2, after.firmware_minor);
  CHECK(after.reset_cause == pp::ResetCause::kUpdate);
  const ph::CommandResult slots = link->Command(pp::SlotsQuery{});
  pp::SlotsReport report{};
  CHECK(slots.Reply(report));
  CHECK(report.slots[1].state == pp::SlotState::kConfirmed);

  r = ph::FlashPackage(*link, Release(1, 1), {});  // older: counter 1 below the board's 2
  LONGS_EQUAL((int)pp::Status::kRollbackRefused, (int)r.status);
  CHECK(r.message.find("anti-rollback counter 1 is below the board's 2") != std::string::npos);
  r = ph::FlashPackage(*link, Release(3, 3, pp::BoardKind::kStm32f4), {});
  LONGS_EQUAL((int)pp::Status::kImageInvalid, (int)r.status);
  CHECK(r.message.find("for a stm32f4 board") != std::string::npos);
  ph::UpdatePackage corrupted = Release(3, 3);
  corrupted.slot_image[0][100] ^= 1;
  r = ph::FlashPackage(*link, corrupted, {});
  LONGS_EQUAL((int)pp::Status::kImageInvalid, (int)r.status);
  LONGS_EQUAL(1, link->board().active_slot);
  // And the next release goes to slot 0.
  r = ph::FlashPackage(*link, Release(3, 3), {});
  CHECK_TEXT(r.status == pp::Status::kOk, r.message.c_str());
  LONGS_EQUAL(0, link->board().active_slot);
}

TEST(Flasher, AWriteCutByALostLinkAtRandomPointsResumesFromWhatTheBoardHas) {
  std::mt19937 rng(17);
  for (int k = 0; k < 4; ++k) {
    pt::SimProcess sim;
    CHECK(sim.Start({"--config", "thesis-pneumatic-3", "--listen", "tcp:127.0.0.1:0"}));
    const size_t budget = 2000 + rng() % 19000;  // bytes the host sends before the cable goes
    {
      auto link = Connect(sim.address(), budget);
      const ph::FlashReport r = ph::FlashPackage(*link, Release(2, 2), {});
      CHECK(r.status != pp::Status::kOk);
      CHECK_TEXT(r.message.find("--resume") != std::string::npos || r.message.find("erase") == 0,
                 r.message.c_str());
    }
    auto link = Connect(sim.address());
    LONGS_EQUAL(0, link->board().active_slot);
    ph::FlashOptions resume;
    resume.resume = true;
    const ph::FlashReport r = ph::FlashPackage(*link, Release(2, 2), resume);
    CHECK_TEXT(r.status == pp::Status::kOk, r.message.c_str());
    CHECK(r.resumed_from + r.bytes_written == Release(2, 2).slot_image[1].size());
    LONGS_EQUAL(1, link->board().active_slot);
  }
}
