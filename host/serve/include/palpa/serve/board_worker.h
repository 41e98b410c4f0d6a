// The threads that call the device for the server: a board lane for everything in order (a set
// waits for the board to apply it), and an urgent lane for E-stop and Release, which never wait
// behind a set.
#pragma once

#include <condition_variable>
#include <deque>
#include <functional>
#include <mutex>
#include <thread>

namespace palpa::serve {

class BoardWorker {
 public:
  BoardWorker();
  ~BoardWorker();  ///< runs what is queued, then stops
  BoardWorker(const BoardWorker&) = delete;
  BoardWorker& operator=(const BoardWorker&) = delete;

  void Post(std::function<void()> job) { board_.Post(std::move(job)); }
  void PostUrgent(std::function<void()> job) { urgent_.Post(std::move(job)); }

 private:
  class Lane {
   public:
    Lane();
    ~Lane();
    void Post(std::function<void()> job);

   private:
    void Run();
    std::mutex mutex_;
    std::condition_variable wake_;
    std::deque<std::function<void()>> jobs_;
    bool stop_ = false;
    std::thread thread_;
  };
  Lane board_, urgent_;
};

}  // namespace palpa::serve
