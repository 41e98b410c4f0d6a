// Firmware update under power cuts: a thousand cuts at random flash bytes of a whole update
// (erase, write, activate, trial boot, confirm), each followed by a boot; the tally of what
// booted, by where the cut fell. A board that boots nothing valid is a failure of the design.
#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <deque>
#include <map>
#include <mutex>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "doc_block.h"
#include "palpa/host/flasher.h"
#include "sim_process.h"
#include "update_scenario.h"

namespace pt = palpa::testing;
namespace ph = palpa::host;

namespace {

/// A UART of `bytes_per_s` each way (1 Mbaud, 8N1: 100 000 bytes/s). Writes return at once, as
/// into a serial driver's buffer, and reach the other end when the line has carried them; reads
/// are delayed by the time the bytes took on the wire.
class PacedTransport final : public ph::Transport {
 public:
  PacedTransport(std::unique_ptr<ph::Transport> inner, double bytes_per_s)
      : inner_(std::move(inner)), bytes_per_s_(bytes_per_s), line_(&PacedTransport::Line, this) {}
  ~PacedTransport() override {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    ready_.notify_all();
    line_.join();
  }
  palpa::protocol::Result<size_t> Read(uint8_t* out, size_t capacity, int timeout_ms) override {
    const palpa::protocol::Result<size_t> r = inner_->Read(out, capacity, timeout_ms);
    if (r.ok() && r.value > 0) {
      std::this_thread::sleep_for(std::chrono::duration<double>(r.value / bytes_per_s_));
    }
    return r;
  }
  ph::Status Write(const uint8_t* data, size_t size) override {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto now = std::chrono::steady_clock::now();
    free_at_ =
        std::max(free_at_, now) + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                      std::chrono::duration<double>(size / bytes_per_s_));
    queue_.push_back({free_at_, std::vector<uint8_t>(data, data + size)});
    ready_.notify_all();
    return ph::Status::kOk;
  }
  std::string Describe() const override { return "paced " + inner_->Describe(); }

 private:
  struct Pending {
    std::chrono::steady_clock::time_point due;
    std::vector<uint8_t> bytes;
  };
  void Line() {
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
      ready_.wait(lock, [&] { return stop_ || !queue_.empty(); });
      if (stop_) return;
      const Pending next = queue_.front();
      queue_.pop_front();
      lock.unlock();
      std::this_thread::sleep_until(next.due);
      inner_->Write(next.bytes.data(), next.bytes.size());
      lock.lock();
    }
  }
  std::unique_ptr<ph::Transport> inner_;
  double bytes_per_s_;
  std::mutex mutex_;
  std::condition_variable ready_;
  std::deque<Pending> queue_;
  std::chrono::steady_clock::time_point free_at_{};
  bool stop_ = false;
  std::thread line_;
};

struct Timing {
  double write_s = 0, total_s = 0;
  std::string message;
};

/// A 64 KiB release flashed into palpa-sim over the paced link.
Timing TimedUpdate(double bytes_per_s) {
  pt::SimProcess sim;
  Timing t;
  if (!sim.Start({"--config", "thesis-pneumatic-3", "--listen", "tcp:127.0.0.1:0"})) {
    t.message = "palpa-sim did not start";
    return t;
  }
  auto transport = ph::OpenTransport(sim.address());
  if (!transport.ok()) {
    t.message = transport.message;
    return t;
  }
  auto link = ph::Link::Open(
      std::make_unique<PacedTransport>(std::move(transport.value), bytes_per_s), ph::LinkOptions{});
  if (!link.ok()) {
    t.message = link.message;
    return t;
  }
  const ph::UpdatePackage release =
      pt::MakeRelease(0, 2, 2, 64 * 1024 - palpa::protocol::ImageSize(0), 1);
  const auto start = std::chrono::steady_clock::now();
  const ph::FlashReport r = ph::FlashPackage(*link.value, release, {});
  t.total_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  t.write_s = r.write_seconds;
  t.message = r.message + " (" + std::to_string(link.value->counters().retransmissions) +
              " retransmissions)";
  return t;
}

}  // namespace

int main(int argc, char** argv) {
  // palpa_update_bench [--cuts N] [DOCS_DIR]
  int cuts = 1000;
  std::string docs;
  for (int i = 1; i < argc; ++i) {
    if (std::string(argv[i]) == "--cuts" && i + 1 < argc) {
      cuts = std::atoi(argv[++i]);
    } else {
      docs = argv[i];
    }
  }
  const uint64_t total = pt::UpdateFlashBytes(1);
  std::mt19937 rng(2026);
  struct Tally {
    int old_image = 0, new_image = 0, none = 0;
  };
  std::map<std::string, Tally> by_phase;
  Tally all;
  for (int k = 0; k < cuts; ++k) {
    // As in the tests: most cuts anywhere, a share among the small record writes at the end.
    const uint64_t cut = k % 10 < 7 ? rng() % (total + 200) : total - 150 + rng() % 300;
    const pt::CutOutcome o = pt::CutPowerDuringUpdate(cut, static_cast<uint32_t>(k + 1));
    Tally& t = by_phase[o.phase];
    if (!o.valid) {
      ++t.none;
      ++all.none;
    } else if (o.is_new) {
      ++t.new_image;
      ++all.new_image;
    } else {
      ++t.old_image;
      ++all.old_image;
    }
  }
  std::printf("== firmware update: %d power cuts over %llu flash bytes of one update ==\n", cuts,
              static_cast<unsigned long long>(total));
  for (const auto& [phase, t] : by_phase) {
    std::printf("  cut during %-14s boots old %4d  new %4d  nothing valid %d\n", phase.c_str(),
                t.old_image, t.new_image, t.none);
  }
  std::printf("  total: old %d, new %d, nothing valid %d\n", all.old_image, all.new_image,
              all.none);
  std::string block =
      "Power cuts at " + std::to_string(cuts) + " random points of one update (" +
      std::to_string(total) +
      " flash bytes):\n\n| cut during | boots the old image | boots the new image | "
      "boots nothing valid |\n|---|---|---|---|\n";
  for (const auto& [phase, t] : by_phase) {
    block += "| " + phase + " | " + std::to_string(t.old_image) + " | " +
             std::to_string(t.new_image) + " | " + std::to_string(t.none) + " |\n";
  }

  // Update time over a UART at 1 Mbaud (100 000 bytes/s each way) against its raw capacity.
  const double rate = 100000;
  const Timing t = TimedUpdate(rate);
  const double raw = 64 * 1024 / rate;
  const double share = t.write_s > 0 ? 100 * raw / t.write_s : 0.0;
  std::printf("== update time: 64 KiB image over a simulated 1 Mbaud link ==\n  %s\n",
              t.message.c_str());
  std::printf(
      "  write %.2f s, whole update %.2f s; the raw link moves 64 KiB in %.2f s: the write runs "
      "at %.0f %% of it\n",
      t.write_s, t.total_s, raw, share);
  char line[400];
  std::snprintf(
      line, sizeof(line),
      "\nA 64 KiB image over a simulated 1 Mbaud UART (100 000 bytes/s each way) into "
      "palpa-sim: writing takes %.2f s, the whole update (erase, write, verify, activate, "
      "reboot, confirm) %.2f s; the link's raw capacity moves 64 KiB in %.2f s, so the "
      "write runs at %.0f %% of it.\n",
      t.write_s, t.total_s, raw, share);
  block += line;
  if (!docs.empty() && !palpa::bench::ReplaceBlock(docs + "/flashing.md", "update-bench", block)) {
    std::fprintf(stderr, "%s/flashing.md has no update-bench block\n", docs.c_str());
    return 1;
  }
  return all.none == 0 && t.write_s > 0 ? 0 : 1;
}
