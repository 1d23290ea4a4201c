// The points of a work-precision plan (`kind = "work-precision"`): each (method, elements,
// courant) triple as the settings of one simulation, and its flat index in the results table.
// The plan reader checks every point with these when it loads a plan; the study
// (study/studies/work_precision.hpp) runs them.
#pragma once

#include <optional>

#include "core/common/parameter_error.hpp"
#include "study/plan/plan.hpp"
#include "study/plan/simulation_settings.hpp"

namespace impactid {

/// The settings of one point: [scene] and [output] of the plan, the method's settings, then
/// `elements` and `courant`, into `settings`. Returns the first error of those two assignments
/// (load_plan() reports it; there is none in a loaded plan).
std::optional<ParameterError> assign_work_precision_point(const Plan& plan, long method,
                                                          long elements, double courant,
                                                          SimulationSettings& settings);

/// The same for a loaded plan, where every point has been built.
SimulationSettings work_precision_settings(const Plan& plan, long method, long elements,
                                           double courant);

/// Flat index of (method, elements, courant) in row-major order, the last fastest.
long work_precision_index(const WorkPrecisionStudy& study, long method, long elements_index,
                          long courant_index);

}  // namespace impactid
