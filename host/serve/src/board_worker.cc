// Two lanes of device calls, each a thread running its jobs in order.
#include "palpa/serve/board_worker.h"

namespace palpa::serve {

BoardWorker::BoardWorker() = default;
BoardWorker::~BoardWorker() = default;

BoardWorker::Lane::Lane() : thread_([this] { Run(); }) {}

BoardWorker::Lane::~Lane() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

void BoardWorker::Lane::Post(std::function<void()> job) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    jobs_.push_back(std::move(job));
  }
  wake_.notify_one();
}

void BoardWorker::Lane::Run() {
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    wake_.wait(lock, [this] { return stop_ || !jobs_.empty(); });
    if (jobs_.empty()) return;  // stopping, and nothing left to run
    std::function<void()> job = std::move(jobs_.front());
    jobs_.pop_front();
    lock.unlock();
    job();
    lock.lock();
  }
}

}  // namespace palpa::serve
