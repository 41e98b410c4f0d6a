// The scene's methods: a scene document checked on the server's thread, the host library's Scene
// opened and fed on the board lane, the pointer's samples coalesced (latest wins) in between.
#include "palpa/serve/scene_methods.h"

#include <algorithm>
#include <chrono>
#include <memory>
#include <mutex>
#include <optional>

#include "palpa/host/scene.h"
#include "palpa/serve/params.h"

namespace palpa::serve {
namespace {

using Json = rpc::Json;

/// Notifications of the scene's state at most this often (a page draws at 30 to 60 Hz).
constexpr double kStateUpdatesPerS = 50;
/// A map sent to a page has at most this many points a side (a finer one is sampled).
constexpr size_t kMapPointsSent = 160;
/// Pointer positions beyond this (mm) from the map's corner are refused as nonsense.
constexpr double kMaxPositionMm = 10000;

struct SceneState {
  SceneState(const protocol::HelloReply& b, std::vector<ServerScene> s)
      : board(b), server_scenes(std::move(s)) {}
  const protocol::HelloReply board;
  const std::vector<ServerScene> server_scenes;

  // The board lane's alone: the scene, what it was made from, the last sample fed.
  std::unique_ptr<host::Scene> scene;
  host::SceneSpec spec;
  host::SceneInput last;

  // Shared between the server's thread and the board lane.
  std::mutex mutex;
  bool running = false;
  std::optional<host::SceneInput> pending;  ///< the newest sample not yet fed
  bool feed_queued = false;                 ///< a feed job is on the board lane
  Json state = Json::object();              ///< the newest state, for notify_scene
  uint64_t generation = 0, sent = 0;
  double next_due_s = 0;
  uint64_t fed = 0, coalesced = 0;
};

double NowS() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

BoardAnswer Error(const rpc::Error& e) { return BoardAnswer{nullptr, e}; }

/// The tissue's map sampled to at most kMapPointsSent a side, rows from y = 0 upwards.
Json MapJson(const host::SceneRenderer& r) {
  const host::TissueMap& t = r.tissue();
  const size_t nx = std::min(t.nx, kMapPointsSent), ny = std::min(t.ny, kMapPointsSent);
  const auto pick = [](size_t k, size_t n, size_t of) {
    return n > 1 ? (k * (of - 1) + (n - 1) / 2) / (n - 1) : 0;
  };
  Json rows = Json::array();
  for (size_t j = 0; j < ny; ++j) {
    Json row = Json::array();
    for (size_t i = 0; i < nx; ++i) row.push_back(t.At(pick(i, nx, t.nx), pick(j, ny, t.ny)));
    rows.push_back(std::move(row));
  }
  const auto [lo, hi] = t.Range();
  return {{"name", t.name},
          {"unit", t.unit},
          {"extent_mm", {t.extent_x_mm(), t.extent_y_mm()}},
          {"range", {lo, hi}},
          {"rendered_range", {r.value_lo(), r.value_hi()}},
          {"has_depth", t.has_depth()},
          {"values", std::move(rows)}};
}

/// What scene.info and scene.load answer: what can be loaded, and what is.
Json InfoJson(SceneState& s) {
  Json names = Json::array();
  for (const ServerScene& sc : s.server_scenes) names.push_back(sc.name);
  Json info = {{"presets", host::ScenePresets()},
               {"server_scenes", names},
               {"max_force_n", host::kMaxInputForceN},
               {"numbering", "fingers from 0, as on the wire"}};
  {
    std::lock_guard<std::mutex> lock(s.mutex);
    info["running"] = s.running;
  }
  info["loaded"] = s.scene != nullptr;
  if (!s.scene) return info;
  const host::SceneRenderer& r = s.scene->renderer();
  Json places = Json::array();
  for (const host::FingerPlace& p : r.layout().fingers) places.push_back({p.dx_mm, p.dy_mm});
  info["name"] = s.spec.name;
  info["description"] = s.spec.description;
  info["tissue"] = MapJson(r);
  info["layout"] = {{"name", r.layout().name},
                    {"places_mm", places},
                    {"contact_diameter_mm", r.layout().contact_diameter_mm}};
  info["fingers"] = s.spec.board_fingers;
  info["contact_force_n"] = r.rule().contact_force_n;
  return info;
}

/// The scene's state after a sample: where the input is and what each finger got.
Json StateJson(const SceneState& s, const host::SceneInput& in,
               const std::vector<host::FingerRender>& renders, bool running) {
  Json fingers = Json::array();
  for (size_t k = 0; k < renders.size() && k < s.spec.board_fingers.size(); ++k) {
    const host::FingerRender& r = renders[k];
    const uint8_t f = s.spec.board_fingers[k];
    const bool jamming = s.board.fingers[f].kind == protocol::FingerKind::kJamming;
    fingers.push_back({{"finger", f},
                       {"touching", r.touching},
                       {"value", r.value},
                       {"u", r.u},
                       {"target", r.mapped.target / 1000.0},
                       {"unit", jamming ? "N/mm" : "mm"}});
  }
  return {{"running", running},
          {"name", s.spec.name},
          {"input", {{"x_mm", in.x_mm}, {"y_mm", in.y_mm}, {"force_n", in.force_n}}},
          {"fingers", std::move(fingers)}};
}

/// A new state for every client (notify_scene).
void Publish(SceneState& s, Json state) {
  std::lock_guard<std::mutex> lock(s.mutex);
  s.state = std::move(state);
  ++s.generation;
}

/// Stops feeding: no sample waits, none is fed after this.
void Halt(SceneState& s) {
  std::lock_guard<std::mutex> lock(s.mutex);
  s.running = false;
  s.pending.reset();
  s.feed_queued = false;
  s.state["running"] = false;
  ++s.generation;
}

/// Feeds the newest waiting sample (the board lane): the ones before it were overtaken.
BoardAnswer FeedLatest(SceneState& s, host::Device&) {
  host::SceneInput in;
  {
    std::lock_guard<std::mutex> lock(s.mutex);
    s.feed_queued = false;
    if (!s.running || !s.pending || !s.scene) return {};
    in = *s.pending;
    s.pending.reset();
    ++s.fed;
  }
  const auto renders = s.scene->Feed(in);
  if (!renders.ok()) {
    Halt(s);
    Json state = StateJson(s, in, {}, false);
    state["error"] = renders.message;
    Publish(s, std::move(state));
    return Error(Refused(renders.outcome()));
  }
  s.last = in;
  Publish(s, StateJson(s, in, renders.value, true));
  return {};
}

/// The scene from a document (its tissue a preset or a phantom) or a server scene by name.
std::optional<rpc::Error> ReadScene(const Json& params, const SceneState& s, host::SceneSpec& out) {
  if (auto e = OnlyKnown(params, {"scene", "name"})) return e;
  const auto doc = params.find("scene"), name = params.find("name");
  if ((doc == params.end()) == (name == params.end()))
    return BadParam("give either 'scene' (a scene document) or 'name' (a server scene)");
  if (name != params.end()) {
    for (const ServerScene& sc : s.server_scenes) {
      if (name->is_string() && name->get_ref<const std::string&>() == sc.name) {
        out = sc.spec;
        return std::nullopt;
      }
    }
    return BadParam("'name': no server scene " + name->dump() +
                    " (scene.info lists them; palpa serve --scene FILE adds one)");
  }
  if (!doc->is_object()) return BadParam("'scene' must be a scene document (a JSON object)");
  const auto spec = host::ParseScene(doc->dump());
  if (!spec.ok()) return BadParam("scene: " + spec.message);
  if (spec.value.source != host::TissueSource::kPreset &&
      spec.value.source != host::TissueSource::kPhantom) {
    return BadParam(
        "scene: tissue: a client names no file on the server — give a preset or a phantom, or "
        "start palpa serve with --scene FILE and load it by name");
  }
  out = spec.value;
  return std::nullopt;
}

PreparedCall Prepare(const std::shared_ptr<SceneState>& s, const std::string& method,
                     const Json& params) {
  if (method == "scene.info") {
    if (auto e = OnlyKnown(params, {})) return {e, nullptr};
    return {std::nullopt,
            [s](host::Device&) {
              return BoardAnswer{InfoJson(*s), std::nullopt};
            },
            false};
  }
  if (method == "scene.load") {
    host::SceneSpec spec;
    if (auto e = ReadScene(params, *s, spec)) return {e, nullptr};
    return {std::nullopt, [s, spec](host::Device& d) {
              Halt(*s);
              auto scene = host::Scene::Open(spec, d);
              if (!scene.ok()) return Error(Refused(scene.outcome()));
              s->scene = std::move(scene.value);
              s->spec = spec;
              s->last = host::SceneInput{};
              Publish(*s, StateJson(*s, s->last, {}, false));
              return BoardAnswer{InfoJson(*s), std::nullopt};
            }};
  }
  if (method == "scene.start" || method == "scene.stop") {
    if (auto e = OnlyKnown(params, {})) return {e, nullptr};
    const bool start = method == "scene.start";
    return {std::nullopt, [s, start](host::Device&) {
              if (!s->scene) return Error(BadParam("no scene is loaded (scene.load first)"));
              Halt(*s);
              if (start) {
                std::lock_guard<std::mutex> lock(s->mutex);
                s->running = true;
                s->state["running"] = true;
                return BoardAnswer{Json{{"running", true}}, std::nullopt};
              }
              // Stopped: a sample that touches nothing, so every finger goes soft.
              host::SceneInput off = s->last;
              off.force_n = 0;
              off.time_s = NowS();
              const auto renders = s->scene->Feed(off);
              if (!renders.ok()) return Error(Refused(renders.outcome()));
              Publish(*s, StateJson(*s, off, renders.value, false));
              return BoardAnswer{Json{{"running", false}}, std::nullopt};
            }};
  }
  if (method == "scene.pointer") {
    if (auto e = OnlyKnown(params, {"x_mm", "y_mm", "force_n"})) return {e, nullptr};
    host::SceneInput in;
    for (const auto& [key, lo, hi, out] :
         {std::tuple{"x_mm", -kMaxPositionMm, kMaxPositionMm, &in.x_mm},
          std::tuple{"y_mm", -kMaxPositionMm, kMaxPositionMm, &in.y_mm},
          std::tuple{"force_n", 0.0, host::kMaxInputForceN, &in.force_n}}) {
      const auto at = params.find(key);
      if (at == params.end()) return {BadParam(std::string("'") + key + "' is missing"), nullptr};
      if (auto e = ReadNumber(*at, key, lo, hi, *out)) return {e, nullptr};
    }
    in.time_s = NowS();
    {
      std::lock_guard<std::mutex> lock(s->mutex);
      if (!s->running) return {BadParam("the scene is not running (scene.start first)"), nullptr};
    }
    PreparedCall feed{std::nullopt, [s](host::Device& d) { return FeedLatest(*s, d); }};
    feed.admit = [s, in] {  // the newest sample waits; one feed job at a time takes it
      std::lock_guard<std::mutex> lock(s->mutex);
      if (!s->running) return false;
      s->pending = in;
      if (s->feed_queued) {
        ++s->coalesced;
        return false;
      }
      s->feed_queued = true;
      return true;
    };
    return feed;
  }
  return {rpc::Error{rpc::kMethodNotFound, "method not found: '" + method + "'", nullptr}, nullptr};
}

}  // namespace

MethodGroup SceneMethods(const protocol::HelloReply& board,
                         std::vector<ServerScene> server_scenes) {
  auto s = std::make_shared<SceneState>(board, std::move(server_scenes));
  MethodGroup g;
  g.prefix = "scene.";
  g.names = {"scene.info", "scene.load", "scene.start", "scene.stop", "scene.pointer"};
  g.prepare = [s](const std::string& method, const Json& params) {
    return Prepare(s, method, params);
  };
  g.on_control_change = [s] { Halt(*s); };
  g.notification = [s](double now_s) -> Json {
    std::lock_guard<std::mutex> lock(s->mutex);
    if (s->generation == s->sent || now_s < s->next_due_s) return nullptr;
    s->sent = s->generation;
    s->next_due_s = now_s + 1 / kStateUpdatesPerS;
    Json params = s->state;
    params["samples_fed"] = s->fed;
    params["samples_overtaken"] = s->coalesced;
    return {{"method", "notify_scene"}, {"params", std::move(params)}};
  };
  return g;
}

}  // namespace palpa::serve
