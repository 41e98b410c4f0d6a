// Generated phantoms: a block of background stiffness with box inclusions, turned into the
// stiffness map a hand would feel at its surface; the thesis's three-cube phantom as a preset.
#pragma once

#include <string>
#include <vector>

#include "palpa/host/outcome.h"
#include "palpa/host/scene_tissue.h"

namespace palpa::host {

/// A box inside the block: its centre in the surface plane, its footprint, its thickness
/// (vertical extent), how far its top lies below the surface, and its stiffness.
struct Inclusion {
  std::string name;
  double x_mm = 0, y_mm = 0;
  double size_x_mm = 0, size_y_mm = 0;
  double thickness_mm = 0;
  double depth_mm = 0;
  double stiffness = 0;  ///< in the phantom's unit
};

struct PhantomSpec {
  std::string name;
  std::string description;  ///< where its numbers come from
  std::string unit = "kPa";
  double size_x_mm = 0, size_y_mm = 0, height_mm = 0;
  double background = 0;  ///< the block's stiffness, in `unit`
  double pitch_mm = 0.5;  ///< of the map it becomes
  std::vector<Inclusion> inclusions;
};

/// Whether a spec describes a block that can be built: positive sizes and stiffnesses, every
/// inclusion inside the block (footprint within the surface, depth + thickness ≤ height), a map
/// within kMaxTissuePoints. The reason names the field ("inclusions[1].depth_mm: ...").
Outcome CheckPhantom(const PhantomSpec& spec);

/// The map of a phantom's surface stiffness: at each point, the column under it as springs in
/// series — background over the height not taken by inclusions, each inclusion over its
/// thickness: E = H / (Σ thickness_i / E_i), so a thicker or stiffer inclusion is felt more. Its
/// depth moves nothing on this map (a 2-D map has no depth); it only has to fit. Inclusions that
/// overlap in plan stack in the column; overlapping in the column is refused.
Result<TissueMap> GeneratePhantom(const PhantomSpec& spec);

/// The thesis's palpation phantom (§5.3.4.2): a silicone block with plastic cubes A, B and C,
/// 4, 12 and 8 mm thick. What the thesis does not give is palpa's choice, said in `description`.
PhantomSpec ThreeCubePhantom();

}  // namespace palpa::host
