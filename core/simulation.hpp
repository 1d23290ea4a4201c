// One rod-impact simulation: assemble the scene, run one method over the time grid, record the
// contact node at every sample t_i = i·Δt (i = 1..N; the initial state is not a sample) and
// return a summary. Numerical failure is an outcome, not an exception: an unstable run ends
// early with status `unstable`, its remaining samples NaN.
//
// Thread safety: simulate() is reentrant; give each thread its own SimulationWorkspace.
#pragma once

#include <string>
#include <vector>

#include "core/central_difference.hpp"
#include "core/implicit_integrator.hpp"
#include "core/method.hpp"
#include "core/rod_scene.hpp"
#include "core/state.hpp"

namespace impactid {

enum class RunStatus {
  ok,        ///< every sample finite, energy within the bound
  unstable,  ///< a value became non-finite or the energy exceeded the bound; the run stopped
  failed,    ///< the method could not start (singular effective matrix)
};
const char* to_string(RunStatus status);

struct RunOptions {
  /// A run is `unstable` as soon as the energy ½vᵀMv + ½uᵀKu exceeds this multiple of the
  /// initial energy. Without external work the exact energy never grows, and the stable methods
  /// here stay within a few percent of it (measured: central difference's central-velocity
  /// energy rises ~1% at impact, the implicit methods dissipate), while an unstable mode grows
  /// geometrically, so the bound separates the two long before any value overflows. > 1.
  double energy_growth_limit = 1.5;
};

/// Samples of the contact node (and the energy) at t_i = i·Δt, stored at index i − 1.
struct ContactTrace {
  std::vector<double> pressure;      ///< λ/A [MPa] (central difference: Carpenter's λ_t)
  std::vector<double> velocity;      ///< [mm/s]
  std::vector<double> displacement;  ///< [mm]
  std::vector<double> energy;        ///< [mJ]
  long size() const { return static_cast<long>(pressure.size()); }
};

struct RunSummary {
  RunStatus status = RunStatus::ok;
  std::string message;        ///< why the run is not ok; empty when it is
  long planned_steps = 0;     ///< N
  long steps = 0;             ///< steps completed (N unless the run stopped early)
  double dt = 0.0;            ///< [s]
  double initial_energy = 0;  ///< [mJ]
  double final_energy = 0;    ///< [mJ], at the last completed sample
  double wall_time_s = 0;     ///< set-up and stepping [s]
};

/// Per-thread storage reused from run to run: after the first run of a given size, further
/// runs of that size allocate nothing in the step loop.
struct SimulationWorkspace {
  ImplicitIntegrator implicit;
  CentralDifference central_difference;
  State state;
  ContactTrace trace;
};

/// Runs scene and method (both must be valid: see validate()). The trace is left in
/// workspace.trace.
RunSummary simulate(const RodScene& scene, const MethodParams& method, const RunOptions& options,
                    SimulationWorkspace& workspace);

}  // namespace impactid
