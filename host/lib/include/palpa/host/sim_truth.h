// The simulator's truth channel (JSON lines over TCP), read on a thread of its own: what the
// fingers really did, which the protocol cannot tell (the demo's "achieved", the true output a
// served page plots beside the estimate).
#pragma once

#include <atomic>
#include <cstddef>
#include <deque>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace palpa::host {

class TruthReader {
 public:
  /// Keeps every sample (0), or the newest `keep` of them (a long-running reader).
  explicit TruthReader(size_t keep = 0) : keep_(keep) {}
  struct Sample {
    double t_s;
    std::vector<double> outputs;  ///< per finger: mm (pneumatic) or N/mm (jamming)
  };
  /// `address` as palpa-sim printed it (tcp:127.0.0.1:PORT); false when it cannot connect.
  bool Connect(const std::string& address);
  ~TruthReader();
  std::vector<Sample> Since(double t_s);
  std::vector<Sample> All() { return Since(-1); }
  double now_s();
  /// The newest sample; false before the first.
  bool Latest(Sample& out);

 private:
  void Run();
  int fd_ = -1;
  std::atomic<bool> stop_{false};
  std::thread thread_;
  std::mutex mutex_;
  std::deque<Sample> samples_;
  size_t keep_;
};

}  // namespace palpa::host
