// The simulator's truth channel (JSON lines over TCP), read on a thread of its own: what the
// fingers really did, which the protocol cannot tell (the demo's "achieved").
#pragma once

#include <atomic>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace palpa::cli {

class TruthReader {
 public:
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

 private:
  void Run();
  int fd_ = -1;
  std::atomic<bool> stop_{false};
  std::thread thread_;
  std::mutex mutex_;
  std::vector<Sample> samples_;
};

}  // namespace palpa::cli
