// Scene files (schema palpa-scene): a tissue (a tissue file, force matrices, a generated phantom
// or a preset), a finger layout, the board fingers it drives and the rendering rule, in one JSON
// document that reads back to what was written.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "palpa/host/file_read.h"
#include "palpa/host/outcome.h"
#include "palpa/host/scene_files.h"
#include "palpa/host/scene_fingers.h"
#include "palpa/host/scene_image.h"
#include "palpa/host/scene_phantom.h"
#include "palpa/host/scene_render.h"
#include "palpa/host/scene_tablet.h"
#include "palpa/host/scene_tactile.h"

namespace palpa::host {

/// A scene file names its tissue; it holds no grid itself, so it is small.
inline constexpr FileLimits kSceneFileLimits{"scene file", 256 * 1024};

/// Where a scene's tissue comes from.
enum class TissueSource { kFile, kForceMatrices, kImage, kPhantom, kPreset };

/// A layout as a scene file states it, so that it is written back the same way.
struct LayoutSpec {
  std::string kind = "right-triangle";  ///< right-triangle, row, jamming-pair, custom
  double spacing_mm = 0;                ///< right-triangle, row, jamming-pair
  size_t count = 0;                     ///< row
  std::vector<FingerPlace> places;      ///< custom
  double angle_deg = 0;
  double contact_diameter_mm = 0;
};

/// A pen tablet or touchpad driving the scene ("input": {"tablet": {…}}).
struct TabletSpec {
  PressureForce pressure_force;  ///< the thesis's by default; palpa scene calibrate-input fits one
  double touch_force_n = 1.0;    ///< what a pad without a pressure axis presses with
};

/// The layout a spec makes (RightTriangleLayout, RowLayout, … then Rotated).
FingerLayout MakeLayout(const LayoutSpec& spec);

struct SceneSpec {
  std::string name, description;
  TissueSource source = TissueSource::kPreset;
  std::string tissue_file;  ///< kFile; relative paths are from the scene file's directory
  ForceMatrixScan scan;     ///< kForceMatrices (paths likewise)
  std::string image_file;   ///< kImage (likewise), read with image_scale
  ImageScale image_scale;
  PhantomSpec phantom;  ///< kPhantom
  std::string preset;   ///< kPreset: a phantom preset's name (ScenePresets())
  LayoutSpec layout;
  std::vector<uint8_t> board_fingers;  ///< one per place of the layout, 0-based
  RenderRule rule;
  std::optional<TabletSpec> tablet;    ///< "input.tablet": absent, the thesis's pressure form
  std::optional<TactileSpec> tactile;  ///< "input.tactile": needed to render a tactile array
};

/// The phantom presets a scene may name: "thesis-three-cube".
std::vector<std::string> ScenePresets();

/// A scene from JSON text. `base_dir` is where relative tissue paths start ("" leaves them as
/// written). A bad document is invalid_argument naming the field by its path.
///   {"schema": "palpa-scene", "schema_version": 1, "name": "…", "description": "…",
///    "tissue": {"preset": "thesis-three-cube"} | {"file": "map.json"}
///            | {"force_matrices": {"along_line_pitch_mm": 0.76, "line_pitch_mm": 2,
///                                  "files": [{"path": "d2.csv", "depth_mm": 2}, …]}}
///            | {"image": {"path": "map.pgm", "mm_per_pixel": 0.5, "unit": "kPa",
///                         "value_at_black": 10, "value_at_white": 40}}
///            | {"phantom": {"name", "unit", "size_mm": [x, y, height], "background",
///                           "pitch_mm", "inclusions": [{"name", "centre_mm": [x, y],
///                           "size_mm": [x, y, thickness], "depth_mm", "stiffness"}, …]}},
///    "layout": {"kind": "right-triangle" | "row" | "jamming-pair" | "custom",
///               "spacing_mm", "count" (row), "places_mm": [[dx, dy], …] (custom),
///               "angle_deg" (optional), "contact_diameter_mm"},
///    "fingers": [board finger per place, 0-based],
///    "rule": {"value_range": [lo, hi] (optional), "contrast", "contact_force_n",
///             "pneumatic": {"mapping": "deformation", "range_mm": [lo, hi]}
///                        | {"mapping": "level"}
///                        | {"mapping": "fingertip-stress", "range_kpa": [lo, hi]}},
///    "input" (optional): {"tablet": {"pressure_force": {"a_n", "b_per_level"}, "touch_force_n"},
///                         "tactile": {"elements", "groups": [[element, …] per finger], "unit",
///                                     "value_range": [lo, hi], "hold_s"}}}
Result<SceneSpec> ParseScene(const std::string& text, const std::string& base_dir = "");
/// ParseScene of a file (within kSceneFileLimits), relative paths from its directory.
Result<SceneSpec> LoadScene(const std::string& path);
/// The JSON text ParseScene reads back to the same spec (paths as held in the spec).
Result<std::string> SerializeScene(const SceneSpec& spec);

/// The scene's tissue: the file or matrices read, the phantom or preset generated.
Result<TissueMap> LoadSceneTissue(const SceneSpec& spec);

}  // namespace palpa::host
