// What a run leaves behind, apart from how it was computed: its status and summary, and the
// samples of its contacts. The metrics layer reads these and nothing of the integrators.
#pragma once

#include <limits>
#include <string>
#include <vector>

namespace impactid {

enum class RunStatus {
  ok,        ///< every sample finite, energy within the bound
  unstable,  ///< a value became non-finite or the energy exceeded the bound; the run stopped
  failed,    ///< the method could not start (singular effective matrix), or a scene of bodies has
             ///< no reference to measure the run against (study/studies/evaluation.cpp)
};
const char* to_string(RunStatus status);

/// Samples of the contact node (and the energy) at t_i = i·Δt, stored at index i − 1.
struct ContactTrace {
  std::vector<double> pressure;      ///< λ/A [MPa] (central difference: Carpenter's λ_t)
  std::vector<double> velocity;      ///< [mm/s]
  std::vector<double> displacement;  ///< [mm]; empty unless RunOptions::record_history
  /// [mJ] the energy the `unstable` test checks (RunOptions::energy_growth_limit: central
  /// difference's own); empty unless RunOptions::record_history
  std::vector<double> energy;
  /// λ_0/A of the far wall [MPa]; empty unless the scene has one (RodScene::far_gap).
  std::vector<double> far_pressure;
  /// A scene of bodies (simulate(AssembledScene)): every contact's pressure λ_k/A_k [MPa] and
  /// velocity [mm/s], in scene_contacts() order. pressure, velocity and displacement above
  /// are then the primary contact's. Empty after simulate(RodScene).
  std::vector<std::vector<double>> contact_pressure, contact_velocity;
  long size() const { return static_cast<long>(pressure.size()); }
};

/// Samples of one contact, index i − 1 for sample i (a reference's, or a supplied history's).
struct ContactSamples {
  std::vector<double> pressure;  ///< [MPa]
  std::vector<double> velocity;  ///< [mm/s]
};

struct RunSummary {
  RunStatus status = RunStatus::ok;
  std::string message;        ///< why the run is not ok; empty when it is
  long planned_steps = 0;     ///< N
  long steps = 0;             ///< samples completed (N unless the run stopped early)
  long skipped_steps = 0;     ///< of those, free-flight samples filled in, not computed
  double dt = 0.0;            ///< [s]
  double initial_energy = 0;  ///< [mJ]
  double final_energy = 0;    ///< [mJ], at the last completed sample
  /// Largest penetration of a wall by its contact node over the completed samples [mm]
  /// (u_n − gap and −far_gap − u_0; <= 0 means none), or with a list of constraints (a scene of
  /// bodies) the largest violation of any of them. Tracked only with a far wall or a list (the
  /// single-wall step loop is kept as it was); NaN otherwise.
  double max_penetration = std::numeric_limits<double>::quiet_NaN();
  /// The contact law's counters (core/contact/contact_treatment.hpp): augmented-Lagrangian
  /// iterations over the run, and the steps whose iterations reached the cap before the tolerance.
  long contact_iterations = 0;
  long unconverged_contact_steps = 0;
  /// Central difference: the largest step certified stable with the penalty's springs
  /// (core/contact/stable_step.hpp) [s]; NaN for the other methods, 0 when none can be certified.
  double stable_dt = std::numeric_limits<double>::quiet_NaN();
  /// Something the user should know about an `ok` run: a step above stable_dt, or augmented-
  /// Lagrangian steps that did not reach the tolerance. Empty otherwise.
  std::string warning;
  double wall_time_s = 0;  ///< set-up and stepping [s]
};

}  // namespace impactid
