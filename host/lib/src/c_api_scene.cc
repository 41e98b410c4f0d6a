// The C ABI's scenes and several-finger requests: palpa_set_fingers, palpa_scene_*.
#include <memory>

#include "c_api_device.h"
#include "palpa/c/palpa.h"
#include "palpa/host/scene.h"

namespace ph = palpa::host;
namespace pp = palpa::protocol;
using palpa::c_api::Report;

struct palpa_scene {
  palpa_device* device = nullptr;
  std::unique_ptr<ph::Scene> scene;
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
  return Report(d, d->device->Set(list, wait != 0));
}

int palpa_scene_open(palpa_device* d, const char* path, palpa_scene** out) {
  if (d == nullptr) return static_cast<int>(pp::Status::kInvalidArgument);
  if (path == nullptr || out == nullptr)
    return Fail(d, pp::Status::kInvalidArgument, "palpa_scene_open: path and out must not be NULL");
  *out = nullptr;
  const auto spec = ph::LoadScene(path);
  if (!spec.ok()) return Report(d, spec.outcome());
  auto scene = ph::Scene::Open(spec.value, *d->device);
  if (!scene.ok()) return Report(d, scene.outcome());
  *out = new palpa_scene{d, std::move(scene.value)};
  return PALPA_OK;
}

int palpa_scene_feed(palpa_scene* s, double time_s, double x_mm, double y_mm, double force_n,
                     palpa_finger_render* out, int capacity) {
  if (s == nullptr) return -static_cast<int>(pp::Status::kInvalidArgument);
  const auto renders = s->scene->Feed({time_s, x_mm, y_mm, force_n});
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

void palpa_scene_close(palpa_scene* s) { delete s; }

}  // extern "C"
