// The tube's law, with the board's own reference pressure and atmosphere.
#include "palpa/host/chamber_tube.h"

#include <cmath>

#include "palpa/core/line_pipeline.h"

namespace palpa::host {
namespace {

/// 2 (p_ref + p_atm): the lag at the reference is 1 / (k × this).
double ReferenceSum(protocol::LineKind kind) {
  return 2 * (static_cast<double>(core::ChamberStepMeanPa(kind)) + core::kAtmospherePa);
}

}  // namespace

double TubeConstant(protocol::LineKind kind, double lag_s) {
  return lag_s > 0 ? 1 / (lag_s * ReferenceSum(kind)) : 0;
}

double TubeLag(protocol::LineKind kind, double k) {
  return k > 0 ? 1 / (k * ReferenceSum(kind)) : 0;
}

double TubeChamberAfter(double chamber_pa, double outlet_pa, double k, double dt_s) {
  if (!(k > 0)) return outlet_pa;
  const double rate = k * (outlet_pa + chamber_pa + 2 * static_cast<double>(core::kAtmospherePa));
  return outlet_pa + (chamber_pa - outlet_pa) * std::exp(-rate * dt_s);
}

}  // namespace palpa::host
