// The state of a second-order system at one instant: a copyable value, so that a run can be
// split, restarted or copied per thread without ceremony.
#pragma once

#include <Eigen/Core>

namespace impactid {

struct State {
  Eigen::VectorXd u;        ///< displacement [mm]
  Eigen::VectorXd v;        ///< velocity [mm/s]
  Eigen::VectorXd a;        ///< acceleration [mm/s²]
  double lambda = 0.0;      ///< contact force (Lagrange multiplier) [N], >= 0
  double far_lambda = 0.0;  ///< force of the far wall (SecondOrderSystem::far_gap) [N], >= 0;
                            ///< stays 0 without one
  /// Multipliers of SecondOrderSystem::constraints [N], >= 0; empty for a system without the
  /// list (lambda and far_lambda then hold the contact forces).
  Eigen::VectorXd multipliers;
  double t = 0.0;  ///< time [s]
};

}  // namespace impactid
