// Hard ceilings per regulator class, compiled in: no configuration can exceed them.
#pragma once

#include <cstdint>

#include "palpa/protocol/enums.h"

// A build may lower (never raise beyond the regulator's range) these with -D options.
#ifndef PALPA_CEILING_PRESSURE_PA
#define PALPA_CEILING_PRESSURE_PA 100000
#endif
#ifndef PALPA_CEILING_VACUUM_PA
#define PALPA_CEILING_VACUUM_PA (-100000)
#endif
#ifndef PALPA_CEILING_BIAS_PA
#define PALPA_CEILING_BIAS_PA 20000
#endif

namespace palpa::core {

struct Ceiling {
  int32_t min_pa;
  int32_t max_pa;
};

static_assert(PALPA_CEILING_PRESSURE_PA > 0 && PALPA_CEILING_PRESSURE_PA <= 100000);
static_assert(PALPA_CEILING_VACUUM_PA < 0 && PALPA_CEILING_VACUUM_PA >= -100000);
static_assert(PALPA_CEILING_BIAS_PA > 0 && PALPA_CEILING_BIAS_PA <= PALPA_CEILING_PRESSURE_PA);

/// The range a line of this kind may ever be commanded to (ITV0010: 0..100 kPa, ITV0090:
/// 0..−100 kPa, jamming bias: 0..20 kPa so the air cushion stays flat).
constexpr Ceiling CeilingFor(protocol::LineKind kind) {
  switch (kind) {
    case protocol::LineKind::kVacuum:
      return {PALPA_CEILING_VACUUM_PA, 0};
    case protocol::LineKind::kBias:
      return {0, PALPA_CEILING_BIAS_PA};
    case protocol::LineKind::kPressure:
    default:
      return {0, PALPA_CEILING_PRESSURE_PA};
  }
}

/// A line's command range, lowest first (a vacuum line's runs downwards, from 0 % to 100 % of the
/// signal): what its regulator can be told. Validation keeps the limits inside it.
constexpr Ceiling CommandRange(int32_t command_min_pa, int32_t command_max_pa) {
  return command_min_pa < command_max_pa ? Ceiling{command_min_pa, command_max_pa}
                                         : Ceiling{command_max_pa, command_min_pa};
}

}  // namespace palpa::core
