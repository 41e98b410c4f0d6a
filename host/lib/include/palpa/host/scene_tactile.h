// Tactile arrays (tele-manipulated instruments) as scene inputs: N element values per sample,
// from a recorded file or over UDP, averaged over each finger's group of elements (the thesis
// drove its three channels from three groups, its jamming pair from two). A stream that stops or
// arrives out of order holds its last sample for a bounded time; then the fingers go soft.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "palpa/host/file_read.h"
#include "palpa/host/outcome.h"

namespace palpa::host {

inline constexpr size_t kMaxTactileElements = 1024;
/// The longest a stream's last sample may be held (the fingers stay stiff on stale data no
/// longer than this).
inline constexpr double kMaxTactileHoldS = 2.0;

/// What the scene file says of its tactile array ("input": {"tactile": {…}}).
struct TactileSpec {
  size_t elements = 0;                      ///< values per sample, 1 … 1 024
  std::vector<std::vector<size_t>> groups;  ///< one per finger of the layout: element indices
  std::string unit;                         ///< the elements' unit ("kPa", "N", "counts", …)
  double value_lo = 0, value_hi = 1;        ///< a group's mean mapped to u = 0 … 1 (rising)
  double hold_s = 0.1;                      ///< how long a stopped stream's last sample holds
};

/// One group per finger (`fingers`), each 1 … elements indices below `elements`, none twice in a
/// group; a rising value range; hold 0 … kMaxTactileHoldS. The reason names the field from
/// "tactile." ("tactile.groups[1][2]: element 9 is beyond the array's 9 (0 … 8)").
Outcome CheckTactile(const TactileSpec& spec, size_t fingers);

/// Each group's mean of `values` (which hold spec.elements values), in group order.
std::vector<double> GroupMeans(const TactileSpec& spec, const std::vector<double>& values);

/// One sample of the array.
struct TactileFrame {
  double time_s = 0;  ///< the file's time, or the arrival time (CLOCK_MONOTONIC) of a packet
  uint32_t sequence = 0;
  std::vector<double> values;
};

/// A recorded stream: the header `time_s,` then one name per element (any names; their count
/// must be the array's), then a frame per line, time rising strictly, every value finite.
inline constexpr FileLimits kTactileStreamLimits{"tactile stream", 256 * 1024 * 1024};
Result<std::vector<TactileFrame>> ParseTactileStream(const std::string& text,
                                                     const std::string& source, size_t elements);
Result<std::vector<TactileFrame>> LoadTactileStream(const std::string& path, size_t elements);

/// A UDP datagram carries one frame, little-endian: the magic "PTA1", a u32 sequence number
/// (rising by one a frame, wrapping), a u16 element count, a u16 of zero, then the count's
/// float32 values. Decoding checks every part and names what is wrong.
inline constexpr size_t kTactileHeaderBytes = 12;
std::vector<uint8_t> EncodeTactilePacket(uint32_t sequence, const std::vector<double>& values);
Result<TactileFrame> DecodeTactilePacket(const uint8_t* data, size_t size, size_t elements);

/// The last good frame, held for `hold_s` after it arrived. A frame whose sequence number is
/// not after the latest (a late or duplicated packet, compared as wrapping u32) is dropped.
class TactileHold {
 public:
  explicit TactileHold(double hold_s) : hold_s_(hold_s) {}
  /// Takes a frame arriving at `now_s`; false (and counted late) when it is older than the held
  /// one.
  bool Receive(const TactileFrame& frame, double now_s);
  /// The values to render at `now_s`: the held frame's while it is younger than hold_s, nothing
  /// (the fingers go soft) after, or before any frame.
  const std::vector<double>* At(double now_s) const;
  size_t late() const { return late_; }
  /// Frames never seen: the gaps in the sequence numbers received.
  size_t missing() const { return missing_; }

 private:
  double hold_s_;
  std::optional<TactileFrame> held_;
  double arrived_s_ = 0;
  size_t late_ = 0, missing_ = 0;
};

/// A UDP socket receiving tactile frames.
class TactileUdp {
 public:
  /// Binds `host:port` (host empty: every address; port 0: one the system picks, see port()).
  static Result<std::unique_ptr<TactileUdp>> Open(const std::string& host, uint16_t port,
                                                  size_t elements);
  ~TactileUdp();
  TactileUdp(const TactileUdp&) = delete;
  TactileUdp& operator=(const TactileUdp&) = delete;
  /// Waits up to `timeout_ms` for a datagram: its frame (time: the arrival on CLOCK_MONOTONIC),
  /// nothing on time-out. A malformed datagram is counted and skipped, never rendered.
  Result<std::optional<TactileFrame>> Receive(int timeout_ms);
  uint16_t port() const { return port_; }
  size_t malformed() const { return malformed_; }
  /// Why the last malformed datagram was refused.
  const std::string& last_problem() const { return last_problem_; }

 private:
  TactileUdp(int fd, uint16_t port, size_t elements) : fd_(fd), port_(port), elements_(elements) {}
  int fd_;
  uint16_t port_;
  size_t elements_;
  size_t malformed_ = 0;
  std::string last_problem_;
};

/// Seconds on CLOCK_MONOTONIC (the clock evdev and UDP arrivals are stamped on).
double MonotonicSeconds();

}  // namespace palpa::host
