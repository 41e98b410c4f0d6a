// The C ABI's scenes and several-finger requests: palpa_set_fingers, palpa_scene_*.
#include <memory>

#include "c_api_device.h"
#include "palpa/c/palpa.h"
#include "palpa/host/scene.h"
#include "palpa/host/scene_evdev.h"

namespace ph = palpa::host;
namespace pp = palpa::protocol;
using palpa::c_api::Report;

struct palpa_scene {
  palpa_device* device = nullptr;
  std::unique_ptr<ph::Scene> scene;
  ph::SceneSpec spec;
};

struct palpa_tablet {
  palpa_device* device = nullptr;
  std::unique_ptr<ph::PenTablet> tablet;
};

static_assert(PALPA_TARGET_LEVEL == static_cast<int>(ph::TargetKind::kLevel));
static_assert(PALPA_TARGET_NORMALIZED == static_cast<int>(ph::TargetKind::kNormalized));
static_assert(PALPA_TARGET_STIFFNESS == static_cast<int>(ph::TargetKind::kStiffnessNPerMm));
static_assert(PALPA_TARGET_DEFORMATION == static_cast<int>(ph::TargetKind::kDeformationMm));
static_assert(PALPA_TARGET_PRESSURE == static_cast<int>(ph::TargetKind::kPressureKpa));

namespace {

int Fail(palpa_device* d, pp::Status status, std::string why) {
  return Report(d, ph::Outcome::Fail(status, std::move(why)));
}

/// The renders as C structs (up to `capacity`), and their count, or the negated status.
int Renders(palpa_scene* s, const ph::Result<std::vector<ph::FingerRender>>& renders,
            palpa_finger_render* out, int capacity) {
  if (!renders.ok()) return -Report(s->device, renders.outcome());
  const pp::HelloReply board = s->device->device->info();
  const auto requests = s->scene->renderer().Requests(renders.value);
  for (size_t k = 0; k < renders.value.size() && out != nullptr && static_cast<int>(k) < capacity;
       ++k) {
    const ph::FingerRender& r = renders.value[k];
    const uint8_t finger = requests[k].finger;
    const bool jamming = board.fingers[finger].kind == pp::FingerKind::kJamming;
    out[k] =
        palpa_finger_render{finger,
                            r.touching ? 1 : 0,
                            r.value,
                            r.depth_mm,
                            r.u,
                            r.mapped.target / 1000.0,
                            static_cast<uint8_t>(jamming ? PALPA_UNIT_N_PER_MM : PALPA_UNIT_MM)};
  }
  return static_cast<int>(renders.value.size());
}

}  // namespace

extern "C" {

int palpa_set_fingers(palpa_device* d, const palpa_request* requests, int count, int wait) {
  if (d == nullptr) return static_cast<int>(pp::Status::kInvalidArgument);
  if (requests == nullptr || count < 1 || count > PALPA_MAX_FINGERS) {
    return Fail(d, pp::Status::kInvalidArgument,
                "palpa_set_fingers: 1 … " + std::to_string(PALPA_MAX_FINGERS) + " requests, not " +
                    std::to_string(count));
  }
  std::vector<ph::FingerRequest> list;
  for (int i = 0; i < count; ++i) {
    const palpa_request& r = requests[i];
    if (r.kind < PALPA_TARGET_LEVEL || r.kind > PALPA_TARGET_PRESSURE) {
      return Fail(d, pp::Status::kInvalidArgument,
                  "palpa_set_fingers: requests[" + std::to_string(i) + "].kind " +
                      std::to_string(r.kind) + " is not a PALPA_TARGET_ kind");
    }
    list.push_back({r.finger, {static_cast<ph::TargetKind>(r.kind), r.value}});
  }
  // Through palpa serve a set always returns once the board applied it.
  return Report(d, d->served ? d->served->Set(list) : d->device->Set(list, wait != 0));
}

int palpa_scene_open(palpa_device* d, const char* path, palpa_scene** out) {
  if (d == nullptr) return static_cast<int>(pp::Status::kInvalidArgument);
  if (path == nullptr || out == nullptr)
    return Fail(d, pp::Status::kInvalidArgument, "palpa_scene_open: path and out must not be NULL");
  *out = nullptr;
  if (d->served) return palpa::c_api::NotThroughServe(d, "palpa_scene_open");
  const auto spec = ph::LoadScene(path);
  if (!spec.ok()) return Report(d, spec.outcome());
  auto scene = ph::Scene::Open(spec.value, *d->device);
  if (!scene.ok()) return Report(d, scene.outcome());
  *out = new palpa_scene{d, std::move(scene.value), spec.value};
  return PALPA_OK;
}

int palpa_scene_feed(palpa_scene* s, double time_s, double x_mm, double y_mm, double force_n,
                     palpa_finger_render* out, int capacity) {
  if (s == nullptr) return -static_cast<int>(pp::Status::kInvalidArgument);
  return Renders(s, s->scene->Feed({time_s, x_mm, y_mm, force_n}), out, capacity);
}

int palpa_scene_predict(palpa_scene* s, int on, double* horizon_s) {
  if (s == nullptr) return static_cast<int>(pp::Status::kInvalidArgument);
  if (on == 0) return Report(s->device, s->scene->Predict(std::nullopt));
  const auto delay = s->scene->DisplayDelay();
  if (!delay.ok()) return Report(s->device, delay.outcome());
  ph::PredictorOptions o;
  o.horizon_s = delay.value;
  if (horizon_s != nullptr) *horizon_s = delay.value;
  return Report(s->device, s->scene->Predict(o));
}

int palpa_scene_feed_tactile(palpa_scene* s, const double* values, int count,
                             palpa_finger_render* out, int capacity) {
  if (s == nullptr) return -static_cast<int>(pp::Status::kInvalidArgument);
  if (!s->spec.tactile) {
    return -Fail(s->device, pp::Status::kUnavailable,
                 "palpa_scene_feed_tactile: the scene has no input.tactile section");
  }
  const ph::TactileSpec& t = *s->spec.tactile;
  if (values == nullptr)
    return Renders(s, s->scene->FeedValues(nullptr, t.value_lo, t.value_hi), out, capacity);
  if (count != static_cast<int>(t.elements)) {
    return -Fail(s->device, pp::Status::kInvalidArgument,
                 "palpa_scene_feed_tactile: " + std::to_string(count) +
                     " values, the scene's array has " + std::to_string(t.elements));
  }
  const std::vector<double> means = ph::GroupMeans(t, std::vector<double>(values, values + count));
  return Renders(s, s->scene->FeedValues(&means, t.value_lo, t.value_hi), out, capacity);
}

int palpa_tablet_open(palpa_scene* s, const char* path, palpa_tablet** out) {
  if (s == nullptr) return static_cast<int>(pp::Status::kInvalidArgument);
  if (path == nullptr || out == nullptr)
    return Fail(s->device, pp::Status::kInvalidArgument,
                "palpa_tablet_open: path and out must not be NULL");
  *out = nullptr;
  const ph::TissueMap& tissue = s->scene->renderer().tissue();
  const ph::TabletSpec t = s->spec.tablet.value_or(ph::TabletSpec{});
  auto tablet = ph::PenTablet::Open(path, tissue.extent_x_mm(), tissue.extent_y_mm(),
                                    t.pressure_force, t.touch_force_n);
  if (!tablet.ok()) return Report(s->device, tablet.outcome());
  *out = new palpa_tablet{s->device, std::move(tablet.value)};
  return PALPA_OK;
}

int palpa_tablet_next(palpa_tablet* t, int timeout_ms, palpa_input* out) {
  if (t == nullptr || out == nullptr) return -static_cast<int>(pp::Status::kInvalidArgument);
  const auto sample = t->tablet->Next(timeout_ms);
  if (!sample.ok()) return -Report(t->device, sample.outcome());
  if (!sample.value) return 0;
  *out = palpa_input{sample.value->time_s, sample.value->x_mm, sample.value->y_mm,
                     sample.value->force_n};
  return 1;
}

void palpa_tablet_close(palpa_tablet* t) { delete t; }

void palpa_scene_close(palpa_scene* s) { delete s; }

}  // extern "C"
