// The indicators a study can store, with units and definitions: the one list behind plan
// files' `[output] indicators`, HDF5 attributes and CSV headers.
#pragma once

#include <span>
#include <string_view>

#include "metrics/evaluation.hpp"

namespace impactid {

struct IndicatorInfo {
  const char* name;        ///< "eps_p"
  const char* units;       ///< "1" when dimensionless (the UDUNITS spelling)
  const char* definition;  ///< stored as the dataset's `definition` attribute
  /// The indicator's place in an evaluation: read for tables, written when a stored row is
  /// read back (a resumed optimisation replays its recorded evaluations).
  double& (*field)(Evaluation&);

  double value(const Evaluation& e) const { return field(const_cast<Evaluation&>(e)); }
};

/// eps_p, eps_v, nop_p, nop_v, p_max, p_max_ratio, contact_episodes, energy_ratio,
/// far_contact_episodes, impacts, max_penetration, wall_time_s.
std::span<const IndicatorInfo> indicator_table();
const IndicatorInfo* find_indicator(std::string_view name);

}  // namespace impactid
