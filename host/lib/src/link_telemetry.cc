// Telemetry from the board: lost frames counted, board time mapped to host time, and every frame
// handed to the subscribers on the dispatcher thread, so a slow one delays only itself.
#include <thread>

#include "palpa/host/link.h"

namespace palpa::host {

void Link::OnTelemetry(const pp::Telemetry& t, double now) {  // mutex_ held
  ++counters_.telemetry_frames;
  const uint64_t span = static_cast<uint64_t>(t.tick_count) * t.sample_interval_us;
  if (expected_next_sample_us_ != 0 && t.first_sample_us > expected_next_sample_us_ && span > 0) {
    counters_.telemetry_lost += (t.first_sample_us - expected_next_sample_us_ + span / 2) / span;
  }
  expected_next_sample_us_ = t.first_sample_us + span;
  // Clock mapping: the smallest host-minus-board offset seen is the least delayed frame.
  const double scale = session_.board().time_scale;
  const double board_end_s =
      static_cast<double>(t.first_sample_us + (t.tick_count ? span - t.sample_interval_us : 0)) /
      1e6 / scale;
  const double offset = now - board_end_s;
  if (offset < window_min_offset_s_) window_min_offset_s_ = offset;
  if (now - offset_window_start_s_ > 10.0 || min_offset_s_ > 1e299) {  // follow slow drift
    min_offset_s_ = window_min_offset_s_;
    window_min_offset_s_ = 1e300;
    offset_window_start_s_ = now;
  }
  if (offset < min_offset_s_) min_offset_s_ = offset;
  // Of what waiters on changed_ wait for, telemetry moves only the applied generations: waking
  // every waiter (heartbeats, commands) for each frame cost thousands of wake-ups a second.
  if (setpoints_.applied != t.setpoint_generation || targets_.applied != t.target_generation) {
    setpoints_.applied = t.setpoint_generation;
    targets_.applied = t.target_generation;
    changed_.notify_all();
  }
  if (subscribers_.empty()) return;
  if (queue_.size() >= options_.subscriber_queue) {
    queue_.pop_front();
    ++counters_.subscriber_dropped;
  }
  queue_.push_back(
      TelemetryFrame{t, min_offset_s_ + static_cast<double>(t.first_sample_us) / 1e6 / scale});
  queue_changed_.notify_one();
}

void Link::DispatchLoop() {
  std::unique_lock<std::mutex> lock(mutex_);
  while (true) {
    queue_changed_.wait(lock, [&] { return stop_ || !queue_.empty(); });
    if (stop_) return;
    const TelemetryFrame frame = queue_.front();
    queue_.pop_front();
    // One subscriber at a time, looked up afresh: one that unsubscribed meanwhile is not called.
    for (auto it = subscribers_.begin(); it != subscribers_.end() && !stop_;) {
      const int id = it->first;
      const auto callback = it->second;
      running_subscriber_ = id;
      lock.unlock();
      (*callback)(frame);  // outside the lock: may take its time
      lock.lock();
      running_subscriber_ = 0;
      callback_returned_.notify_all();
      it = subscribers_.upper_bound(id);
    }
  }
}

int Link::Subscribe(std::function<void(const TelemetryFrame&)> callback) {
  std::lock_guard<std::mutex> lock(mutex_);
  const int id = next_subscriber_++;
  subscribers_[id] =
      std::make_shared<std::function<void(const TelemetryFrame&)>>(std::move(callback));
  return id;
}

void Link::Unsubscribe(int id) {
  std::unique_lock<std::mutex> lock(mutex_);
  subscribers_.erase(id);
  if (std::this_thread::get_id() == dispatcher_.get_id()) return;  // from its own callback
  callback_returned_.wait(lock, [&] { return running_subscriber_ != id; });
}

double Link::BoardToHostSeconds(uint64_t board_us) const {
  std::lock_guard<std::mutex> lock(mutex_);
  const double scale = session_.board().time_scale > 0 ? session_.board().time_scale : 1.0;
  return min_offset_s_ + static_cast<double>(board_us) / 1e6 / scale;
}

}  // namespace palpa::host
