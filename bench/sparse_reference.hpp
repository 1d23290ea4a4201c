// The straightforward way to step the rod with HHT and Lagrange contact: a general sparse
// matrix, Eigen's SparseLU refactorised every step, contact through the augmented (saddle
// point) system. It is the yardstick for the tridiagonal kernel in core/: same equations, same
// contact rule, so the same numbers, at the cost a general-purpose code would pay.
#pragma once

#include <vector>

#include "core/methods/method.hpp"
#include "core/model/rod_scene.hpp"

namespace impactid {

/// Contact pressure at every sample t_i, i = 1..N (as ContactTrace::pressure).
std::vector<double> sparse_reference_pressure(const RodScene& scene, const HhtParams& params);

}  // namespace impactid
