// The truth side channel: true pressures, deformations and stiffnesses as JSON lines, for tests,
// benchmarks and the demo. Nothing in the protocol or the control path reads it.
#pragma once

#include <cstdint>
#include <string>

#include "palpa/hal/linux/atomic_file.h"
#include "palpa/hal/sim/plant.h"

namespace palpa::sim {

class TruthStream {
 public:
  ~TruthStream();
  /// "file:PATH" (written whole: the file appears complete when Close puts it in place) or
  /// "tcp:HOST:PORT" (one reader at a time; nothing is kept while none is there).
  /// Refused naming --truth: the file's status (AtomicFile::Open), or kUnavailable when the port
  /// cannot be listened on.
  hal::Done Open(const std::string& spec);
  /// Puts a file in place; kIoError naming --truth when it could not be written.
  hal::Done Close();
  const std::string& address() const { return address_; }
  /// Board-side facts for tests that judge the safe state from outside.
  struct BoardFacts {
    bool safe = false;
    uint32_t faults = 0;
    uint64_t last_host_frame_us = 0;
  };
  void Write(const PlantTruth& truth, uint64_t board_time_us, const BoardFacts& board);
  /// Accepts a waiting reader (TCP). Never blocks.
  void Pump();

  /// One JSON line for a truth sample (no trailing newline).
  static std::string Format(const PlantTruth& truth, uint64_t board_time_us,
                            const BoardFacts& board);

 private:
  hal::linux_files::AtomicFile file_;
  int listen_fd_ = -1;
  int client_fd_ = -1;
  std::string address_;
};

}  // namespace palpa::sim
