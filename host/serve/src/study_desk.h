// A served study session: the library's runner on a thread of its own, the participant's answers
// handed to it from the API, and each event queued for the view that may see it.
#pragma once

#include <atomic>
#include <condition_variable>
#include <deque>
#include <mutex>
#include <optional>
#include <thread>

#include "palpa/host/study_runner.h"
#include "palpa/serve/json_rpc.h"
#include "palpa/serve/study_methods.h"

namespace palpa::serve {

class StudyDesk {
 public:
  explicit StudyDesk(StudyServeOptions options) : options_(std::move(options)) {}
  ~StudyDesk();  ///< stops a running session and waits for it (the board released)

  const StudyServeOptions& options() const { return options_; }

  /// Starts a session (the board lane): returns once the runner has claimed `out_dir` and
  /// written session.json, or with the runner's refusal.
  host::Outcome Start(host::Device& device, const host::Study& study,
                      const std::string& participant, const std::string& out_dir,
                      const std::string& shown_dir, bool resume);
  /// The participant's answer to trial `trial`: checked against the trial asked, handed over.
  host::Outcome Answer(int trial, const host::StudyAnswer& answer);
  /// The participant moves on (from a finger shown alone, or from a break).
  host::Outcome Next(int trial);
  /// Stops the session: no further Set, waits end; the caller releases the board.
  host::Outcome Stop(const std::string& why);
  bool running();

  /// What each view is told on joining.
  rpc::Json ParticipantState();
  rpc::Json ExperimenterState();
  /// The queued channel notifications ({"channel", "method", "params"}).
  std::vector<rpc::Json> Take();

 private:
  class Participant;
  enum class Waiting { kNone, kFeel, kAnswer, kBreak };

  void Run(host::Device& device, host::Study study, host::StudyRunOptions o);
  /// Under the lock: the participant's state changed (a full snapshot, numbered).
  void PublishParticipant(rpc::Json state);
  void PublishExperimenter(rpc::Json params);
  /// Waits (runner thread) until the participant acts, the session stops, or `until` is true.
  void Await(std::unique_lock<std::mutex>& lock, const std::function<bool()>& until);
  void OnTrigger(const host::TriggerEvent& e);
  void OnProgress(const std::string& line);

  const StudyServeOptions options_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::thread thread_;
  std::atomic<bool> stop_{false};
  bool running_ = false, started_ = false, ended_ = false;
  host::Outcome end_;
  Waiting waiting_ = Waiting::kNone;
  host::TrialPrompt prompt_;
  std::optional<host::StudyAnswer> answer_;
  bool next_ = false;
  rpc::Json participant_ = {{"state", "idle"}, {"seq", 0}};
  uint64_t seq_ = 0;
  rpc::Json session_ = nullptr;  ///< the experimenter's view of the session
  std::deque<rpc::Json> queue_;
};

}  // namespace palpa::serve
