#include "core/run/simulation.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <initializer_list>
#include <limits>
#include <string>

#include "core/common/overloaded.hpp"
#include "core/contact/constraint_list_law.hpp"
#include "core/contact/contact_law_registry.hpp"
#include "core/contact/stable_step_warning.hpp"
#include "core/methods/method_registry.hpp"
#include "core/methods/stepper_coefficients.hpp"
#include "core/model/second_order_system.hpp"

namespace impactid {

const char* to_string(RunStatus status) {
  switch (status) {
    case RunStatus::ok:
      return "ok";
    case RunStatus::unstable:
      return "unstable";
    case RunStatus::failed:
      return "failed";
  }
  return "unknown";
}

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

void reset_trace(ContactTrace& trace, long samples, bool history, bool far_wall) {
  const auto n = static_cast<std::size_t>(samples);
  trace.pressure.assign(n, kNaN);
  trace.velocity.assign(n, kNaN);
  trace.displacement.assign(history ? n : 0, kNaN);
  trace.energy.assign(history ? n : 0, kNaN);
  trace.far_pressure.assign(far_wall ? n : 0, kNaN);
  trace.contact_pressure.clear();
  trace.contact_velocity.clear();
}

// The step loop shared by every method and scene, from sample `first` on. `stepper.advance`
// produces the state at the next sample time and `stepper.energy` the energy of that sample (the
// method's own: RunOptions::energy_growth_limit); `record` stores sample i of the state's
// contacts, `finite` says whether those contact values are finite. They are lambdas, so the calls
// are inlined: no virtual dispatch inside the loop. Histories record the displacement of
// `history_dof`.
template <class Stepper, class Record, class Finite>
void run_steps(const RunOptions& options, long first, Eigen::Index history_dof, State& state,
               ContactTrace& trace, RunSummary& summary, Stepper&& stepper, Record&& record,
               Finite&& finite) {
  const double energy_bound = options.energy_growth_limit * summary.initial_energy;
  const bool history = options.record_history;
  const long last = summary.planned_steps - 1;
  for (long i = first; i <= last; ++i) {
    stepper.advance(state);
    record(i, state);
    summary.steps = i + 1;
    // The bound is checked at the same steps whether or not histories are recorded, so that
    // recording them never changes the status.
    const bool check = i == last || (i - first + 1) % options.energy_check_interval == 0;
    if (history) {
      trace.displacement[i] = state.u[history_dof];
      trace.energy[i] = stepper.energy(state);
    }
    if (check) {
      const double energy = history ? trace.energy[i] : stepper.energy(state);
      summary.final_energy = energy;
      if (!std::isfinite(energy)) {
        summary.status = RunStatus::unstable;
        summary.message = "non-finite values at t = " + format_value(state.t) + " s";
        return;
      }
      if (summary.initial_energy > 0.0 && energy > energy_bound) {
        summary.status = RunStatus::unstable;
        summary.message = "energy grew to " + format_value(energy / summary.initial_energy) +
                          " times the initial energy at t = " + format_value(state.t) +
                          " s (bound " + format_value(options.energy_growth_limit) + ")";
        return;
      }
    }
    if (!finite(state)) {
      summary.status = RunStatus::unstable;
      summary.message = "non-finite values at t = " + format_value(state.t) + " s";
      return;
    }
  }
}

// The rod's two named contacts: the main wall's pressure and node, and with kFarWall the far
// wall's pressure and the largest penetration; with kMainPenetration (a contact law that lets the
// node penetrate) the single wall's largest penetration (the Lagrange single-wall loop records
// nothing more).
template <bool kFarWall, bool kMainPenetration, class Stepper>
void run_rod_steps(const SecondOrderSystem& system, double area, const RunOptions& options,
                   long first, State& state, ContactTrace& trace, RunSummary& summary,
                   Stepper&& stepper) {
  const Eigen::Index c = system.contact_dof;
  run_steps(
      options, first, c, state, trace, summary, stepper,
      [&](long i, const State& s) {
        trace.pressure[i] = s.lambda / area;
        trace.velocity[i] = s.v[c];
        if constexpr (kFarWall) {
          trace.far_pressure[i] = s.far_lambda / area;
          const double penetration =
              std::max(s.u[c] - system.gap, -system.far_gap - s.u[system.far_contact_dof]);
          summary.max_penetration = std::max(summary.max_penetration, penetration);
        } else if constexpr (kMainPenetration) {
          summary.max_penetration = std::max(summary.max_penetration, s.u[c] - system.gap);
        }
      },
      [&](const State& s) {
        return std::isfinite(s.lambda) && std::isfinite(s.v[c]) &&
               !(kFarWall && !std::isfinite(s.far_lambda));
      });
}

// A scene with a constraint list (of bodies, or a model's `system`): every contact's pressure and
// velocity, the primary contact's also in the trace's main columns, and the largest penetration
// of any constraint.
template <SemiDiscreteSystem System, class Stepper>
void run_listed_steps(const AssembledScene& scene, const System& system, const RunOptions& options,
                      long first, State& state, ContactTrace& trace, RunSummary& summary,
                      Stepper&& stepper) {
  const auto m = static_cast<Eigen::Index>(scene.probes.size());
  const auto primary = static_cast<std::size_t>(scene.primary);
  run_steps(
      options, first, scene.probes[primary].velocity_dof, state, trace, summary, stepper,
      [&](long i, const State& s) {
        for (Eigen::Index k = 0; k < m; ++k) {
          const ContactProbe& probe = scene.probes[static_cast<std::size_t>(k)];
          trace.contact_pressure[static_cast<std::size_t>(k)][i] = s.multipliers[k] / probe.area;
          trace.contact_velocity[static_cast<std::size_t>(k)][i] = s.v[probe.velocity_dof];
          summary.max_penetration =
              std::max(summary.max_penetration,
                       constraint_violation(system.constraints[static_cast<std::size_t>(k)], s.u));
        }
        trace.pressure[i] = trace.contact_pressure[primary][i];
        trace.velocity[i] = trace.contact_velocity[primary][i];
      },
      [&](const State& s) {
        for (Eigen::Index k = 0; k < m; ++k) {
          if (!std::isfinite(s.multipliers[k]) ||
              !std::isfinite(s.v[scene.probes[static_cast<std::size_t>(k)].velocity_dof])) {
            return false;
          }
        }
        return true;
      });
}

// What run_steps() calls per sample: `advance` a state by one sample, and the `energy` of the
// sample it produced.
template <class Advance, class Energy>
struct LoopStepper {
  Advance advance;
  Energy energy;
};
// Clang 14 (the sanitizer build's) does not deduce an aggregate's arguments by itself.
template <class Advance, class Energy>
LoopStepper(Advance, Energy) -> LoopStepper<Advance, Energy>;

// The energy ½vᵀMv + ½uᵀKu of a state: every method's but central difference's and KR-α's.
template <SemiDiscreteSystem System>
auto plain_energy(const System& system) {
  return [&system](const State& s) { return system.energy(s.u, s.v); };
}

// Copies a stepper's contact-law counters into the summary, with a warning when steps ended at
// the iteration cap.
template <class Stepper>
void count_contact_iterations(const Stepper& stepper, RunSummary& summary) {
  summary.contact_iterations = stepper.contact_iterations();
  summary.unconverged_contact_steps = stepper.unconverged_contact_steps();
  if (summary.unconverged_contact_steps > 0 && summary.warning.empty()) {
    summary.warning = std::to_string(summary.unconverged_contact_steps) +
                      " step(s) ended the augmented-Lagrangian iterations at the cap before the "
                      "tolerance: raise augmented_max_iterations or the penalty stiffness";
  }
}

// Why an integrator could not start: a sparse one says why (the failed pivot's DOF, a mass that
// is not diagonal), a tridiagonal one fails only on a singular matrix, which `otherwise` names.
template <class Integrator>
std::string start_failure(const Integrator& integrator, const char* otherwise) {
  if constexpr (requires { integrator.failure(); }) {
    return integrator.failure();
  } else {
    return otherwise;
  }
}

// The failure message of a stepper of several integrators: the first that says why.
template <class Integrator>
std::string first_failure(std::initializer_list<const Integrator*> integrators) {
  if constexpr (requires(const Integrator& i) { i.failure(); }) {
    for (const Integrator* i : integrators) {
      if (!i->failure().empty()) return i->failure();
    }
    return "the effective matrix cannot be factored";
  } else {
    return "singular effective matrix";
  }
}

// Why an explicit stage scheme could not start: on a tridiagonal system only a singular M; on a
// sparse model its stage contact names the pivot.
template <class Stepper>
std::string mass_failure(const Stepper& stepper) {
  if constexpr (requires { stepper.stage_contact().failure(); }) {
    return stepper.stage_contact().failure();
  } else {
    return "singular mass matrix";
  }
}

// The two-stage explicit schemes, Noh–Bathe's and Kim's (core/methods/noh_bathe.hpp,
// kim_explicit.hpp), on either kind of system: the stable step (with the penalty's springs) is
// reported, and a step above it is flagged before the run starts (the run still goes, as central
// difference's does: the energy bound then stops it). `name` and the parameter p, the
// coefficients and the critical Ωₙ are the scheme's.
template <SemiDiscreteSystem System, class Coefficients, class Stepper, class Run>
void run_two_stage_explicit(const System& system, const char* name, double p,
                            const Coefficients& coefficients, double critical_omega, double dt,
                            const ContactPenalties& contact, Stepper& stepper, State& state,
                            RunSummary& summary, Run&& run) {
  if (!stepper.initialize(system, coefficients, dt, state, contact)) {
    summary.status = RunStatus::failed;
    summary.message = std::string(name) + ": " + mass_failure(stepper);
    return;
  }
  summary.stable_dt = stepper.stable_step();
  summary.warning = stable_step_warning(stepper, name, p, critical_omega, dt, contact.law);
  run(LoopStepper{[&](State& s) { stepper.step(system, s); }, plain_energy(system)});
  count_contact_iterations(stepper, summary);
}

// The KR-α explicit method (core/methods/kr_alpha.hpp): unconditionally stable with every contact
// law (the penalty's springs solved with its forward increment), so there is no stable step to
// report.
template <SemiDiscreteSystem System, class Stepper, class Run>
void run_kr_alpha(const System& system, const std::string& name,
                  const KrAlphaCoefficients& coefficients, double dt,
                  const ContactPenalties& contact, Stepper& stepper, State& state,
                  RunSummary& summary, Run&& run) {
  if (!stepper.initialize(system, coefficients, dt, state, contact)) {
    summary.status = RunStatus::failed;
    summary.message = name + ": " + stepper.failure();
    return;
  }
  run(LoopStepper{[&](State& s) { stepper.step(system, s); },
                  [&](const State& s) { return stepper.energy(system, s); }});
  count_contact_iterations(stepper, summary);
}

// Central difference's stable step (with the penalty's springs) into the summary, and a penalty
// run above it flagged before it starts.
template <class Stepper>
void flag_penalty_step(const Stepper& stepper, double dt, const ContactPenalties& contact,
                       RunSummary& summary) {
  summary.stable_dt = stepper.stable_step();
  if (contact.explicit_force() && !stepper.within_stability_limit()) {
    summary.warning = "dt = " + format_value(dt) +
                      " s exceeds central difference's stable step with the penalty springs, " +
                      (stepper.stable_step() > 0.0 ? format_value(stepper.stable_step()) + " s"
                                                   : std::string("which needs a diagonal mass")) +
                      ": lower the step or the penalty stiffness";
  }
}

// Initialises the method's stepper on the system from `state` and hands run() a LoopStepper; a
// stepper that cannot start marks the run failed. One dispatch for both systems (the workspace's
// steppers for `System`: core/run/steppers.hpp), on the stepper the method's descriptor names by
// its coefficients (core/methods/stepper_coefficients.hpp), not on the method.
template <SemiDiscreteSystem System, class Run>
void run_method(const System& system, const MethodParams& method, double dt,
                const ContactPenalties& contact, SimulationWorkspace& ws, State& state,
                RunSummary& summary, Run&& run) {
  Steppers<System>& steppers = ws.steppers<System>();
  const std::string name = descriptor(method).name;
  const auto fail = [&](const std::string& prefix, const std::string& why) {
    summary.status = RunStatus::failed;
    summary.message = prefix + ": " + why;
  };
  // The steppers that take the system's energy and report their contact iterations alike.
  const auto run_plain = [&](auto& stepper) {
    run(LoopStepper{[&](State& s) { stepper.step(system, s); }, plain_energy(system)});
    count_contact_iterations(stepper, summary);
  };
  std::visit(
      Overloaded{
          [&](const ImplicitCoefficients& coefficients) {
            auto& stepper = steppers.implicit;
            if (stepper.initialize(system, coefficients, dt, contact)) {
              run_plain(stepper);
            } else {
              fail(name, start_failure(stepper, "singular effective matrix"));
            }
          },
          [&](const CompositeCoefficients& coefficients) {
            auto& stepper = steppers.composite;
            if (stepper.initialize(system, coefficients, dt, contact)) {
              run_plain(stepper);
            } else {
              const std::string first = start_failure(stepper.first(), "singular effective matrix");
              fail(name, first.empty() ? start_failure(stepper.second(), "") : first);
            }
          },
          [&](const HouboltCoefficients&) {
            auto& houbolt = steppers.houbolt;
            if (houbolt.initialize(system, dt, contact)) {
              run_plain(houbolt);
            } else {
              fail(name, first_failure({&houbolt.first(), &houbolt.second(), &houbolt.steady()}));
            }
          },
          [&](const WilsonThetaCoefficients& coefficients) {
            auto& wilson = steppers.wilson_theta;
            if (wilson.initialize(system, coefficients, dt, contact)) {
              run_plain(wilson);
            } else {
              fail(name, first_failure({&wilson.extended()}));
            }
          },
          [&](const NohBatheCoefficients& coefficients) {
            run_two_stage_explicit(system, name.c_str(), coefficients.p, coefficients,
                                   noh_bathe_critical_omega(coefficients.p), dt, contact,
                                   steppers.noh_bathe, state, summary, run);
          },
          [&](const KimExplicitCoefficients& coefficients) {
            run_two_stage_explicit(system, name.c_str(), coefficients.p, coefficients,
                                   kim_explicit_critical_omega(coefficients.p), dt, contact,
                                   steppers.kim_explicit, state, summary, run);
          },
          [&](const KrAlphaCoefficients& coefficients) {
            run_kr_alpha(system, name, coefficients, dt, contact, steppers.kr_alpha, state,
                         summary, run);
          },
          [&](const CentralDifferenceCoefficients& coefficients) {
            auto& stepper = steppers.central_difference;
            if (stepper.initialize(system, coefficients.velocity, dt, state, contact)) {
              flag_penalty_step(stepper, dt, contact, summary);
              stepper.step(system, state);  // the state at t_k: the initial state or a filled-in
                                            // sample
              run(LoopStepper{[&](State& s) { stepper.step(system, s); },
                              [&](const State& s) { return stepper.energy(system, s); }});
              count_contact_iterations(stepper, summary);
            } else {
              fail("central difference", start_failure(stepper, "singular left-hand matrix"));
            }
          },
      },
      stepper_coefficients(method));
}

}  // namespace

RunSummary simulate(const RodScene& scene, const MethodParams& method, const RunOptions& options,
                    SimulationWorkspace& ws) {
  const auto start = std::chrono::steady_clock::now();
  RunSummary summary = simulate(assemble(scene), method, options, ws);
  // Set-up includes the assembly, as it always did for the rod.
  summary.wall_time_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return summary;
}

long free_flight_samples(double first_contact_time, double dt, long step_count, bool rigid_flight,
                         const RunOptions& options) {
  if (!options.skip_free_flight || !rigid_flight || !std::isfinite(first_contact_time)) return 0;
  return std::clamp(static_cast<long>(std::floor(first_contact_time / dt) - 2.0), 0L, step_count);
}

bool prepare_run(const AssembledScene& scene, const RunOptions& options, ContactTrace& trace,
                 State& state, RunSummary& summary) {
  const SecondOrderSystem& system = scene.system;
  const SparseSystem* sparse = scene.sparse.get();
  const Eigen::Index n = sparse ? sparse->size() : system.size();
  const double dt = scene.dt;
  const std::size_t contacts = scene.probes.size();
  const bool listed = sparse || system.has_constraint_list();
  const std::vector<Constraint>& constraints = sparse ? sparse->constraints : system.constraints;
  const bool far_wall = !sparse && system.has_far_contact();  // the rod's named far wall

  summary = RunSummary{};
  summary.planned_steps = scene.step_count;
  summary.dt = dt;
  reset_trace(trace, scene.step_count, options.record_history, far_wall);
  if (scene.contact_columns) {
    trace.contact_pressure.resize(contacts);
    trace.contact_velocity.resize(contacts);
    for (std::size_t k = 0; k < contacts; ++k) {
      trace.contact_pressure[k].assign(static_cast<std::size_t>(scene.step_count), kNaN);
      trace.contact_velocity[k].assign(static_cast<std::size_t>(scene.step_count), kNaN);
    }
  }
  if (const auto error = validate(options.contact)) {
    summary.status = RunStatus::failed;
    summary.message =
        "run options: " + error->field + " = " + error->value + ": " + error->constraint;
    return false;
  }
  if (options.energy_check_interval < 1 || !(options.energy_growth_limit > 1.0)) {
    summary.status = RunStatus::failed;
    summary.message = "run options: energy_check_interval must be >= 1 and energy_growth_limit > 1";
    return false;
  }
  if (contacts == 0) {
    summary.status = RunStatus::failed;
    summary.message = "the scene has no contact: add a wall or a second body";
    return false;
  }

  if (scene.initial_displacement.size() == n) {
    state.u = scene.initial_displacement;
  } else {
    state.u.setZero(n);
  }
  state.v = scene.initial_velocity;
  state.lambda = 0.0;
  state.far_lambda = 0.0;
  state.multipliers.setZero(listed ? static_cast<Eigen::Index>(contacts) : 0);
  state.t = 0.0;
  // Zero for a built-in scene without damping.
  state.a =
      sparse ? consistent_acceleration(*sparse, state) : consistent_acceleration(system, state);
  summary.initial_energy =
      sparse ? sparse->energy(state.u, state.v) : system.energy(state.u, state.v);
  summary.final_energy = summary.initial_energy;

  // Rigid free flight of every body, filled in (free_flight_samples). The fill is u = v0·t from
  // u = 0: a scene that starts otherwise (a clamped end, an initial displacement) is stepped from
  // t = 0 whatever its rigid_flight says.
  const bool rigid_flight =
      scene.rigid_flight && scene.starts_free && scene.initial_displacement.size() == 0;
  const long skipped =
      free_flight_samples(scene.first_contact_time, dt, scene.step_count, rigid_flight, options);
  const ContactProbe& primary = scene.probes[static_cast<std::size_t>(scene.primary)];
  const bool main_penetration = !listed && !far_wall && descriptor(options.contact.law).springs;
  if (listed || far_wall || main_penetration) summary.max_penetration = -kInf;
  for (long i = 0; i < skipped; ++i) {
    const double t = (i + 1) * dt;
    if (far_wall) {
      const double u = scene.initial_velocity[system.contact_dof] * t;
      const double u_far = scene.initial_velocity[system.far_contact_dof] * t;
      trace.far_pressure[i] = 0.0;
      summary.max_penetration =
          std::max({summary.max_penetration, u - system.gap, -system.far_gap - u_far});
    }
    for (std::size_t k = 0; k < contacts && scene.contact_columns; ++k) {
      trace.contact_pressure[k][i] = 0.0;
      trace.contact_velocity[k][i] = scene.initial_velocity[scene.probes[k].velocity_dof];
      if (listed) {
        const Constraint& c = constraints[k];
        double g = -c.gap;
        if (c.plus >= 0) g += scene.initial_velocity[c.plus] * t;
        if (c.minus >= 0) g -= scene.initial_velocity[c.minus] * t;
        summary.max_penetration = std::max(summary.max_penetration, g);
      }
    }
    if (main_penetration) {
      summary.max_penetration = std::max(
          summary.max_penetration, scene.initial_velocity[system.contact_dof] * t - system.gap);
    }
    trace.pressure[i] = 0.0;
    trace.velocity[i] = scene.initial_velocity[primary.velocity_dof];
    if (options.record_history) {
      trace.displacement[i] = scene.initial_velocity[primary.velocity_dof] * t;
      trace.energy[i] = summary.initial_energy;
    }
  }
  if (skipped > 0) {
    state.t = skipped * dt;
    state.u = scene.initial_velocity * state.t;
  }
  summary.steps = summary.skipped_steps = skipped;

  return true;
}

RunSummary simulate(const AssembledScene& scene, const MethodParams& method,
                    const RunOptions& options, SimulationWorkspace& ws) {
  const auto start = std::chrono::steady_clock::now();
  const SecondOrderSystem& system = scene.system;
  const bool listed = system.has_constraint_list();
  const bool far_wall = system.has_far_contact();  // the rod's named far wall
  RunSummary summary;
  State& state = ws.state;
  if (!prepare_run(scene, options, ws.trace, state, summary)) return summary;
  if (has_massless_dofs(scene.mass)) {
    if (auto refusal = massless_refusal(descriptor(method), 0.0)) {
      summary.status = RunStatus::failed;
      summary.message = std::string("mass = ") + to_string(scene.mass) + ": " + *refusal;
      return summary;
    }
  }
  if (auto refusal = contact_law_refusal(descriptor(method), options.contact.law)) {
    summary.status = RunStatus::failed;
    summary.message = std::string("contact = ") + to_string(options.contact.law) + ": " + *refusal;
    return summary;
  }
  const long skipped = summary.skipped_steps;
  const ContactProbe& primary = scene.probes[static_cast<std::size_t>(scene.primary)];

  if (scene.sparse) {  // a user's model with sparse matrices
    const SparseSystem& sparse = *scene.sparse;
    const ContactPenalties contact = resolve_contact(options.contact, sparse);
    run_method(sparse, method, scene.dt, contact, ws, state, summary, [&](const auto& stepper) {
      run_listed_steps(scene, sparse, options, skipped, state, ws.trace, summary, stepper);
    });
    summary.wall_time_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return summary;
  }

  // The step loop; the far wall's bookkeeping only when the system has the named one.
  const ContactPenalties contact = resolve_contact(options.contact, system);
  run_method(system, method, scene.dt, contact, ws, state, summary, [&](const auto& stepper) {
    if (listed) {
      run_listed_steps(scene, system, options, skipped, state, ws.trace, summary, stepper);
    } else if (far_wall) {
      run_rod_steps<true, false>(system, primary.area, options, skipped, state, ws.trace, summary,
                                 stepper);
    } else if (!contact.lagrange()) {
      run_rod_steps<false, true>(system, primary.area, options, skipped, state, ws.trace, summary,
                                 stepper);
    } else {
      run_rod_steps<false, false>(system, primary.area, options, skipped, state, ws.trace, summary,
                                  stepper);
    }
  });
  if (!listed && scene.contact_columns) {  // the one contact's samples are the main columns
    ws.trace.contact_pressure[0] = ws.trace.pressure;
    ws.trace.contact_velocity[0] = ws.trace.velocity;
  }
  summary.wall_time_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return summary;
}

}  // namespace impactid
