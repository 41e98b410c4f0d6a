// The server's API, apart from the network: clients come and go, their messages are read as
// JSON-RPC 2.0 and answered, control is given to one of them, telemetry goes out to subscribers,
// and the board is released whenever its controller goes away. Everything here runs on the
// server's one thread, except the device calls, which run on the board worker and post back.
#pragma once

#include <atomic>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "palpa/host/device.h"
#include "palpa/host/sim_truth.h"
#include "palpa/serve/board_methods.h"
#include "palpa/serve/board_worker.h"
#include "palpa/serve/control.h"
#include "palpa/serve/json_rpc.h"
#include "palpa/serve/serve_options.h"
#include "palpa/serve/telemetry_hub.h"

namespace palpa::serve {

/// One connected client as the API sees it: somewhere to send text.
class Peer {
 public:
  virtual ~Peer() = default;
  /// Answers and control notices: always delivered (a client that cannot take them is closed).
  virtual void Send(std::string text) = 0;
  /// Telemetry: dropped (false) while the client has not taken what it was sent before.
  virtual bool SendDroppable(std::string text) = 0;
};

class Api {
 public:
  /// Runs a function on the server's thread (posted from the board worker's).
  using PostToServer = std::function<void(std::function<void()>)>;

  /// The board's methods are there from the start; `groups` adds others (a scene's).
  Api(host::Device& device, const ServeOptions& options, PostToServer post,
      std::vector<MethodGroup> groups = {});
  ~Api();

  ClientId Connect(std::shared_ptr<Peer> peer, const std::string& description);
  /// A client closed, or (`why`) went silent: if it controlled, the board is released.
  void Disconnect(ClientId id, const std::string& why);
  void OnMessage(ClientId id, std::string_view text);
  /// A message over the size limit, read and dropped: answered with an error.
  void OnTooLarge(ClientId id, size_t bytes);
  /// A binary message: JSON-RPC here is text, so it is answered with a parse error.
  void OnBinary(ClientId id);
  /// Telemetry notifications that are due, and the link's events; called every few ms.
  void Tick(double now_s);

  /// A simulator's truth channel, read from now on: each notify_telemetry carries the newest
  /// true output of every finger ("finger_truth") and its board time.
  void SetTruth(std::unique_ptr<host::TruthReader> truth) { truth_ = std::move(truth); }

  /// Counters for the log and the benchmark.
  rpc::Json Stats() const;

 private:
  struct Client {
    std::shared_ptr<Peer> peer;
    std::string name;
    std::vector<Subscription> subscriptions;
    uint64_t telemetry_dropped = 0;
    std::set<std::string> channels;  ///< the groups' channels joined ("study.participant")
    bool alone = false;              ///< its channels only: no group's notification for all
  };

  /// One call: an answer now (server methods), later (board jobs) or none (notifications).
  void Dispatch(ClientId id, const rpc::Call& call,
                const std::shared_ptr<struct BatchAnswer>& batch);
  std::optional<rpc::Json> ServerMethod(ClientId id, const rpc::Call& call);
  /// A call to a group's method: checked, control required where it acts, then a board job.
  void GroupMethod(const MethodGroup& group, ClientId id, const rpc::Call& call,
                   const std::shared_ptr<struct BatchAnswer>& batch);
  void Answer(ClientId id, const rpc::Call& call, const std::shared_ptr<struct BatchAnswer>& batch,
              rpc::Json answer);
  /// Control changed: release the board if asked (urgent lane, then again behind any job of the
  /// old controller still queued), and tell every client.
  void ControlChanged(const Control::Change& change, const std::string& reason);
  void Broadcast(const rpc::Json& notification);
  /// The groups' channel notifications, each to the clients in its channel.
  void SendChannels();
  /// On a simulated board, each finger's true output and its board time into a notification.
  void AddTruth(rpc::Json& params);
  /// An error for a message that held no call, to its sender.
  void Refuse(ClientId id, const rpc::Error& error);
  std::string Name(ClientId id) const;

  host::Device& device_;
  ServeOptions options_;
  PostToServer post_;
  protocol::HelloReply board_;
  TelemetryHub hub_;
  int telemetry_subscription_ = 0;
  std::vector<MethodGroup> groups_;
  std::unique_ptr<host::TruthReader> truth_;
  Control control_;
  /// Bumped whenever control changes: a controller's job queued before the change is not sent.
  std::shared_ptr<std::atomic<uint64_t>> control_epoch_;
  std::map<ClientId, Client> clients_;
  ClientId next_id_ = 1;
  uint64_t next_subscription_ = 1;
  uint64_t calls_ = 0, errors_ = 0;
  double next_events_s_ = 0;
  BoardWorker worker_;  ///< last: its threads stop (finishing their jobs) before the rest goes
};

}  // namespace palpa::serve
