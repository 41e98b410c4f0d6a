// The board's telemetry, kept for the server's subscribers: every sample the link delivers goes
// into a ring (nothing decimated between board and server), and each subscription takes from it
// what a page can draw — a notification every 1/updates_per_s with the samples since the last,
// thinned to sample_rate_hz.
#pragma once

#include <array>
#include <cstdint>
#include <mutex>
#include <vector>

#include <nlohmann/json.hpp>

#include "palpa/host/link.h"
#include "palpa/host/stiffness_map.h"

namespace palpa::serve {

struct Subscription {
  uint64_t id = 0;
  double updates_per_s = 30;    ///< notifications a second
  double sample_rate_hz = 100;  ///< samples a second inside them
  uint64_t last_seq = 0;        ///< the newest sample already considered
  uint64_t last_sent_us = 0;    ///< board time of the newest sample sent
  bool sent_any = false;
  double next_due_s = 0;  ///< steady-clock time of the next notification
};

class TelemetryHub {
 public:
  static constexpr size_t kCapacity = 8192;  ///< samples kept (8 s at 1 kHz)

  TelemetryHub(const protocol::HelloReply& board, std::vector<host::FingerCurves> curves);

  /// From the link's dispatcher thread: every tick of the frame into the ring.
  void OnFrame(const host::TelemetryFrame& frame);
  /// The next notification's params for `s` (null when there is nothing new), advancing it.
  nlohmann::json Take(Subscription& s);
  /// Samples received since the start, and samples a subscription missed because the ring
  /// overtook it (a stalled client).
  uint64_t received() const;
  uint64_t overtaken() const { return overtaken_; }
  /// A subscription that starts now: it sends from the newest sample on.
  void Start(Subscription& s) const;

 private:
  struct Tick {
    uint64_t seq = 0;
    uint64_t board_time_us = 0;
    uint32_t faults = 0;
    std::array<protocol::LineSample, protocol::kMaxLines> lines{};
  };

  protocol::HelloReply board_;
  std::vector<host::FingerCurves> curves_;
  mutable std::mutex mutex_;
  std::vector<Tick> ring_;
  uint64_t next_seq_ = 1;
  uint64_t overtaken_ = 0;  ///< touched only by Take (the server's one thread)
};

}  // namespace palpa::serve
