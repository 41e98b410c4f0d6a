// The server's own methods: what it is, who a client is, control, telemetry subscriptions.
#include "palpa/serve/api.h"
#include "palpa/serve/params.h"

namespace palpa::serve {
namespace {

using Json = rpc::Json;

/// The server's own methods; the groups' follow them in server.info.
const char* const kServerMethods[] = {"server.info",         "server.connection.identify",
                                      "control.take",        "control.release",
                                      "telemetry.subscribe", "telemetry.unsubscribe"};

}  // namespace

std::optional<Json> Api::ServerMethod(ClientId id, const rpc::Call& call) {
  const auto error = [&](const rpc::Error& e) { return rpc::ErrorAnswer(call.id, e); };
  const auto result = [&](Json r) { return rpc::Result(call.id, std::move(r)); };
  const Json& p = call.params;
  Client& me = clients_[id];
  if (call.method == "server.info") {
    if (auto e = OnlyKnown(p, {})) return error(*e);
    const std::optional<ClientId> c = control_.controller();
    Json methods(kServerMethods);
    for (const MethodGroup& g : groups_) {
      for (const std::string& name : g.names) methods.push_back(name);
    }
    return result({{"server", "palpa serve"},
                   {"api_version", 1},
                   {"you", id},
                   {"controls", control_.Controls(id)},
                   {"controller", c ? Json(*c) : Json(nullptr)},
                   {"controller_name", c ? clients_[*c].name : ""},
                   {"methods", methods},
                   {"ping_interval_ms", options_.ping_interval_ms},
                   {"missed_pings_gone", options_.missed_pings_gone},
                   {"max_message_bytes", options_.max_message_bytes},
                   {"stats", Stats()}});
  }
  if (call.method == "server.connection.identify") {
    if (auto e = OnlyKnown(p, {"client_name"})) return error(*e);
    const auto name = p.find("client_name");
    if (name == p.end() || !name->is_string() || name->get_ref<const std::string&>().empty() ||
        name->get_ref<const std::string&>().size() > 64)
      return error(BadParam("'client_name' must be a string of 1 to 64 characters"));
    me.name = name->get<std::string>() + ", " + me.name.substr(me.name.rfind(' ') + 1);
    return result({{"client", id}, {"name", me.name}});
  }
  if (call.method == "control.take") {
    if (auto e = OnlyKnown(p, {"force"})) return error(*e);
    bool force = false;
    if (auto e = ReadFlag(p, "force", force)) return error(*e);
    const std::string holder = control_.controller() ? Name(*control_.controller()) : "";
    const bool had = control_.Controls(id);
    const host::Result<Control::Change> change = control_.Take(id, force, holder);
    if (!change.ok())
      return error(
          rpc::Error{rpc::kControlTaken, change.message, {{"controller", *control_.controller()}}});
    if (!had) {
      ControlChanged(change.value, Name(id) + " took control" +
                                       (change.value.previous ? " from " + holder : std::string()));
    }
    return result({{"controls", true}, {"board_released", change.value.release_board}});
  }
  if (call.method == "control.release") {
    if (auto e = OnlyKnown(p, {})) return error(*e);
    const Control::Change change = control_.Leave(id);
    if (change.release_board) ControlChanged(change, Name(id) + " gave control up");
    return result({{"controls", false}, {"board_released", change.release_board}});
  }
  if (call.method == "telemetry.subscribe") {
    if (auto e = OnlyKnown(p, {"updates_per_s", "sample_rate_hz"})) return error(*e);
    Subscription s;
    if (p.contains("updates_per_s")) {
      if (auto e = ReadNumber(p["updates_per_s"], "updates_per_s", 1, 100, s.updates_per_s))
        return error(*e);
    }
    if (p.contains("sample_rate_hz")) {
      if (auto e = ReadNumber(p["sample_rate_hz"], "sample_rate_hz", 1, 1000, s.sample_rate_hz))
        return error(*e);
    }
    if (me.subscriptions.size() >= 4) return error(BadParam("at most 4 subscriptions a client"));
    s.id = next_subscription_++;
    hub_.Start(s);
    me.subscriptions.push_back(s);
    return result({{"subscription", s.id},
                   {"updates_per_s", s.updates_per_s},
                   {"sample_rate_hz", s.sample_rate_hz},
                   {"numbering", "lines and fingers from 0, as on the wire"}});
  }
  if (call.method == "telemetry.unsubscribe") {
    if (auto e = OnlyKnown(p, {"subscription"})) return error(*e);
    int64_t sub = 0;
    if (!p.contains("subscription")) return error(BadParam("'subscription' is missing"));
    if (auto e = ReadInteger(p["subscription"], "subscription", 1, INT64_MAX, sub))
      return error(*e);
    for (auto it = me.subscriptions.begin(); it != me.subscriptions.end(); ++it) {
      if (it->id == static_cast<uint64_t>(sub)) {
        me.subscriptions.erase(it);
        return result({{"unsubscribed", sub}});
      }
    }
    return error(BadParam("no subscription " + std::to_string(sub) + " of this client"));
  }
  return std::nullopt;
}

}  // namespace palpa::serve
