// Clients, their calls, control and telemetry: the API on the server's thread.
#include "palpa/serve/api.h"

#include <cmath>
#include <cstdio>

#include "palpa/serve/board_methods.h"

namespace palpa::serve {
namespace {
using Json = rpc::Json;  // file-local: others of the unity batch alias it in their own
}  // namespace

/// The answers of one message: sent together once every call has one (a batch as an array).
struct BatchAnswer {
  bool batch = false;
  size_t pending = 0;
  std::vector<Json> answers;
};

Api::Api(host::Device& device, const ServeOptions& options, PostToServer post,
         std::vector<MethodGroup> groups)
    : device_(device),
      options_(options),
      post_(std::move(post)),
      board_(device.info()),
      hub_(board_,
           [&device] {
             std::vector<host::FingerCurves> curves;
             for (uint8_t f = 0; f < device.info().finger_count; ++f)
               curves.push_back(device.curves(f));
             return curves;
           }()),
      groups_(std::move(groups)),
      control_epoch_(std::make_shared<std::atomic<uint64_t>>(0)) {
  groups_.insert(groups_.begin(), BoardMethods(board_));
  telemetry_subscription_ =
      device_.Subscribe([this](const host::TelemetryFrame& f) { hub_.OnFrame(f); });
}

Api::~Api() { device_.Unsubscribe(telemetry_subscription_); }

ClientId Api::Connect(std::shared_ptr<Peer> peer, const std::string& description) {
  const ClientId id = next_id_++;
  clients_[id] = Client{std::move(peer), description, {}, 0, {}, false};
  return id;
}

std::string Api::Name(ClientId id) const {
  const auto at = clients_.find(id);
  return "client " + std::to_string(id) +
         (at == clients_.end() ? "" : " (" + at->second.name + ")");
}

void Api::Disconnect(ClientId id, const std::string& why) {
  if (clients_.find(id) == clients_.end()) return;
  const std::string name = Name(id);
  clients_.erase(id);
  const Control::Change change = control_.Leave(id);
  if (change.release_board) {
    std::fprintf(stderr, "palpa serve: %s, the controller, %s: board released\n", name.c_str(),
                 why.c_str());
    ControlChanged(change, name + " " + why);
  }
}

void Api::OnTooLarge(ClientId id, size_t bytes) {
  Refuse(id, rpc::Error{rpc::kTooLarge,
                        "a message of " + std::to_string(bytes) + " bytes or more (at most " +
                            std::to_string(options_.max_message_bytes) + "): dropped unread",
                        nullptr});
}

void Api::OnBinary(ClientId id) {
  Refuse(id, rpc::Error{rpc::kParseError, "parse error: a binary message (JSON-RPC here is text)",
                        nullptr});
}

void Api::Refuse(ClientId id, const rpc::Error& error) {
  ++errors_;
  const auto at = clients_.find(id);
  if (at != clients_.end()) at->second.peer->Send(rpc::Text(rpc::ErrorAnswer(nullptr, error)));
}

void Api::OnMessage(ClientId id, std::string_view text) {
  const auto at = clients_.find(id);
  if (at == clients_.end()) return;
  rpc::Parsed parsed = rpc::ParseMessage(text, options_.max_batch);
  auto batch = std::make_shared<BatchAnswer>();
  batch->batch = parsed.batch;
  batch->answers = std::move(parsed.answers);
  errors_ += batch->answers.size();
  for (const rpc::Call& call : parsed.calls) batch->pending += call.notification ? 0 : 1;
  if (batch->pending == 0 && !batch->answers.empty()) {
    const Json out = batch->batch ? Json(batch->answers) : batch->answers.front();
    at->second.peer->Send(rpc::Text(out));
  }
  for (const rpc::Call& call : parsed.calls) Dispatch(id, call, batch);
}

void Api::Answer(ClientId id, const rpc::Call& call, const std::shared_ptr<BatchAnswer>& batch,
                 Json answer) {
  if (answer.contains("error")) ++errors_;
  if (call.notification) return;
  batch->answers.push_back(std::move(answer));
  if (--batch->pending > 0) return;
  const auto at = clients_.find(id);
  if (at == clients_.end()) return;  // gone meanwhile
  at->second.peer->Send(rpc::Text(batch->batch ? Json(batch->answers) : batch->answers.front()));
}

void Api::Dispatch(ClientId id, const rpc::Call& call, const std::shared_ptr<BatchAnswer>& batch) {
  ++calls_;
  for (const MethodGroup& group : groups_) {
    if (call.method.rfind(group.prefix, 0) == 0) return GroupMethod(group, id, call, batch);
  }
  std::optional<Json> answer = ServerMethod(id, call);
  if (!answer) {
    answer = rpc::ErrorAnswer(
        call.id,
        rpc::Error{rpc::kMethodNotFound, "method not found: '" + call.method + "'", nullptr});
  }
  Answer(id, call, batch, std::move(*answer));
}

void Api::GroupMethod(const MethodGroup& group, ClientId id, const rpc::Call& call,
                      const std::shared_ptr<BatchAnswer>& batch) {
  if (const auto only = group.channel_only.find(call.method); only != group.channel_only.end()) {
    const auto client = clients_.find(id);
    if (client == clients_.end() || !client->second.channels.count(only->second)) {
      const std::string why = call.method + " is taken only from a client in the channel " +
                              only->second + ", not from this one";
      return Answer(id, call, batch,
                    rpc::ErrorAnswer(call.id, rpc::Error{rpc::kNotInChannel, why, nullptr}));
    }
  }
  PreparedCall prepared = group.prepare(call.method, call.params);
  if (!prepared.error && prepared.needs_control && !control_.Controls(id)) {
    prepared.error =
        rpc::Error{rpc::kNotController,
                   call.method + " acts on the board, and " +
                       (control_.controller() ? Name(*control_.controller()) + " controls it"
                                              : std::string("nobody controls it")) +
                       ": take control first (control.take)",
                   nullptr};
  }
  if (prepared.error) return Answer(id, call, batch, rpc::ErrorAnswer(call.id, *prepared.error));
  if (!prepared.join.empty()) {  // one channel of a group at a time
    std::set<std::string>& channels = clients_[id].channels;
    std::erase_if(channels, [&](const std::string& c) { return c.rfind(group.prefix, 0) == 0; });
    channels.insert(prepared.join);
    clients_[id].alone = prepared.join_alone;
  }
  if (prepared.admit && !prepared.admit())  // carried by a job already queued
    return Answer(id, call, batch, rpc::Result(call.id, nullptr));
  const bool urgent = prepared.urgent, needs_control = prepared.needs_control;
  const uint64_t epoch = control_epoch_->load();
  auto job = [this, id, call, batch, epoch, needs_control, job = std::move(prepared.job),
              current = control_epoch_]() {
    BoardAnswer answer;
    if (needs_control && current->load() != epoch) {
      answer.error = rpc::Error{rpc::kNotController,
                                "control passed before this call ran: nothing was sent", nullptr};
    } else {
      answer = job(device_);
    }
    Json out = answer.error ? rpc::ErrorAnswer(call.id, *answer.error)
                            : rpc::Result(call.id, std::move(answer.result));
    post_([this, id, call, batch, out = std::move(out)]() mutable {
      Answer(id, call, batch, std::move(out));
    });
  };
  if (urgent) {
    worker_.PostUrgent(std::move(job));
  } else {
    worker_.Post(std::move(job));
  }
}

void Api::ControlChanged(const Control::Change& change, const std::string& reason) {
  control_epoch_->fetch_add(1);
  for (const MethodGroup& g : groups_) {  // first, so nothing feeds the board past the release
    if (g.on_control_change) g.on_control_change();
  }
  if (change.release_board) {
    // At once, and again behind whatever the old controller had queued, so nothing it sent
    // before losing control re-actuates the board afterwards.
    worker_.PostUrgent([this] { device_.Release(); });
    worker_.Post([this] { device_.Release(); });
  }
  const std::optional<ClientId> now = control_.controller();
  Broadcast(rpc::Notification(
      "notify_control", {{"controller", now ? Json(*now) : Json(nullptr)},
                         {"controller_name", now ? clients_[*now].name : ""},
                         {"previous", change.previous ? Json(*change.previous) : Json(nullptr)},
                         {"board_released", change.release_board},
                         {"reason", reason}}));
}

void Api::Broadcast(const Json& notification) {
  const std::string text = rpc::Text(notification);
  for (auto& [id, client] : clients_) client.peer->Send(text);
}

void Api::SendChannels() {
  for (const MethodGroup& g : groups_) {
    if (!g.channel_notifications) continue;
    for (Json& n : g.channel_notifications()) {
      const std::string channel = n["channel"];
      const std::string text = rpc::Text(rpc::Notification(n["method"], std::move(n["params"])));
      for (auto& [id, client] : clients_) {
        if (client.channels.count(channel)) client.peer->Send(text);
      }
    }
  }
}

void Api::AddTruth(Json& params) {
  host::TruthReader::Sample truth;
  if (truth_ && truth_->Latest(truth)) {  // a simulated board: what the fingers really did
    params["finger_truth"] = truth.outputs;
    params["truth_board_time_us"] = static_cast<uint64_t>(std::llround(truth.t_s * 1e6));
  }
}

void Api::Tick(double now_s) {
  for (auto& [id, client] : clients_) {
    for (Subscription& s : client.subscriptions) {
      if (now_s < s.next_due_s) continue;
      s.next_due_s = std::max(s.next_due_s + 1.0 / s.updates_per_s, now_s);
      Json params = hub_.Take(s);
      if (params.is_null()) continue;
      AddTruth(params);
      if (!client.peer->SendDroppable(
              rpc::Text(rpc::Notification("notify_telemetry", std::move(params)))))
        ++client.telemetry_dropped;
    }
  }
  for (const MethodGroup& g : groups_) {
    if (!g.notification) continue;
    Json n = g.notification(now_s);
    if (n.is_null()) continue;
    AddTruth(n["params"]);
    const std::string text = rpc::Text(rpc::Notification(n["method"], std::move(n["params"])));
    for (auto& [id, client] : clients_) {
      if (!client.alone && !client.peer->SendDroppable(text)) ++client.telemetry_dropped;
    }
  }
  SendChannels();
  if (now_s >= next_events_s_) {  // what happened to the link, told to everyone
    next_events_s_ = now_s + 0.1;
    for (const std::string& event : device_.link().TakeEvents()) {
      std::fprintf(stderr, "palpa serve: %s\n", event.c_str());
      Broadcast(rpc::Notification("notify_board_event", {{"message", event}}));
    }
  }
}

Json Api::Stats() const {
  uint64_t dropped = 0;
  for (const auto& [id, client] : clients_) dropped += client.telemetry_dropped;
  const host::LinkCounters link = device_.link().counters();
  return {{"clients", clients_.size()},
          {"controller", control_.controller() ? Json(*control_.controller()) : Json(nullptr)},
          {"calls", calls_},
          {"errors", errors_},
          {"telemetry_samples", hub_.received()},
          {"telemetry_lost_on_link", link.telemetry_lost},
          {"telemetry_dropped_by_link_subscriber", link.subscriber_dropped},
          {"telemetry_overtaken_in_server", hub_.overtaken()},
          {"telemetry_notifications_dropped", dropped}};
}

}  // namespace palpa::serve
