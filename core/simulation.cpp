#include "core/simulation.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "core/second_order_system.hpp"

namespace impactid {

const char* to_string(RunStatus status) {
  switch (status) {
    case RunStatus::ok: return "ok";
    case RunStatus::unstable: return "unstable";
    case RunStatus::failed: return "failed";
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
}

// Samples before which the rod is certainly still in rigid free flight: every method computes
// u = v0·t, v = v0, a = 0 there exactly, so they can be filled in. Central difference's λ at t_i
// looks ahead to t_{i+1}, hence one step of margin beyond the last sample before the impact.
long free_flight_samples(const RodScene& scene, const RodSceneDerived& d,
                         const RunOptions& options) {
  if (!options.skip_free_flight || scene.rayleigh_mass != 0.0 || !std::isfinite(d.impact_time)) {
    return 0;
  }
  const double before_impact = std::floor(d.impact_time / d.time_step) - 2.0;
  return std::clamp(static_cast<long>(before_impact), 0L, d.step_count);
}

// The step loop shared by every method, from sample `first` on. `advance` produces the state at
// the next sample time; it is a lambda, so the call is inlined: no virtual dispatch inside the
// loop. kFarWall adds the far wall's bookkeeping (its pressure, the largest penetration); the
// single-wall instantiation is the loop as it was.
template <bool kFarWall, class Advance>
void run_steps(const SecondOrderSystem& system, double area, const RunOptions& options,
               long first, State& state, ContactTrace& trace, RunSummary& summary,
               Advance&& advance) {
  const Eigen::Index c = system.contact_dof;
  const double energy_bound = options.energy_growth_limit * summary.initial_energy;
  const bool history = options.record_history;
  const long last = summary.planned_steps - 1;
  for (long i = first; i <= last; ++i) {
    advance(state);
    trace.pressure[i] = state.lambda / area;
    trace.velocity[i] = state.v[c];
    if constexpr (kFarWall) {
      trace.far_pressure[i] = state.far_lambda / area;
      const double penetration =
          std::max(state.u[c] - system.gap, -system.far_gap - state.u[system.far_contact_dof]);
      summary.max_penetration = std::max(summary.max_penetration, penetration);
    }
    summary.steps = i + 1;
    // The bound is checked at the same steps whether or not histories are recorded, so that
    // recording them never changes the status.
    const bool check = i == last || (i - first + 1) % options.energy_check_interval == 0;
    if (history) {
      trace.displacement[i] = state.u[c];
      trace.energy[i] = system.energy(state.u, state.v);
    }
    if (check) {
      const double energy = history ? trace.energy[i] : system.energy(state.u, state.v);
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
    if (!std::isfinite(state.lambda) || !std::isfinite(state.v[c]) ||
        (kFarWall && !std::isfinite(state.far_lambda))) {
      summary.status = RunStatus::unstable;
      summary.message = "non-finite values at t = " + format_value(state.t) + " s";
      return;
    }
  }
}

}  // namespace

RunSummary simulate(const RodScene& scene, const MethodParams& method, const RunOptions& options,
                    SimulationWorkspace& ws) {
  const auto start = std::chrono::steady_clock::now();
  const RodSceneDerived derived = derive(scene);
  const SecondOrderSystem system = assemble_rod(scene);
  const Eigen::Index n = system.size();
  const double dt = derived.time_step;

  RunSummary summary;
  summary.planned_steps = derived.step_count;
  summary.dt = dt;
  const bool far_wall = system.has_far_contact();
  reset_trace(ws.trace, derived.step_count, options.record_history, far_wall);
  if (options.energy_check_interval < 1 || !(options.energy_growth_limit > 1.0)) {
    summary.status = RunStatus::failed;
    summary.message = "run options: energy_check_interval must be >= 1 and energy_growth_limit > 1";
    return summary;
  }

  State& state = ws.state;
  state.u.setZero(n);
  state.v.setConstant(n, scene.velocity);
  state.lambda = 0.0;
  state.far_lambda = 0.0;
  state.t = 0.0;
  state.a = consistent_acceleration(system, state);  // zero without damping
  summary.initial_energy = system.energy(state.u, state.v);
  summary.final_energy = summary.initial_energy;

  // Rigid free flight, filled in: the state at t_k = k·Δt and the samples 1..k.
  const long skipped = free_flight_samples(scene, derived, options);
  if (far_wall) summary.max_penetration = -kInf;
  for (long i = 0; i < skipped; ++i) {
    if (far_wall) {
      const double u = scene.velocity * ((i + 1) * dt);
      ws.trace.far_pressure[i] = 0.0;
      summary.max_penetration =
          std::max({summary.max_penetration, u - scene.gap, -*scene.far_gap - u});
    }
    ws.trace.pressure[i] = 0.0;
    ws.trace.velocity[i] = scene.velocity;
    if (options.record_history) {
      ws.trace.displacement[i] = scene.velocity * ((i + 1) * dt);
      ws.trace.energy[i] = summary.initial_energy;
    }
  }
  if (skipped > 0) {
    state.t = skipped * dt;
    state.u.setConstant(n, scene.velocity * state.t);
  }
  summary.steps = summary.skipped_steps = skipped;

  // The step loop, with the far wall's bookkeeping only when the scene has one.
  const auto run = [&](const auto& advance) {
    if (far_wall) {
      run_steps<true>(system, scene.area, options, skipped, state, ws.trace, summary, advance);
    } else {
      run_steps<false>(system, scene.area, options, skipped, state, ws.trace, summary, advance);
    }
  };
  if (const auto* cdm = std::get_if<CentralDifferenceParams>(&method)) {
    CentralDifference& stepper = ws.central_difference;
    if (stepper.initialize(system, cdm->velocity, dt, state)) {
      stepper.step(system, state);  // the state at t_k: the initial state or a filled-in sample
      run([&](State& s) { stepper.step(system, s); });
    } else {
      summary.status = RunStatus::failed;
      summary.message = "central difference: singular left-hand matrix";
    }
  } else {
    ImplicitIntegrator& stepper = ws.implicit;
    if (stepper.initialize(system, implicit_coefficients(method), dt)) {
      run([&](State& s) { stepper.step(system, s); });
    } else {
      summary.status = RunStatus::failed;
      summary.message = std::string(to_string(kind_of(method))) + ": singular effective matrix";
    }
  }
  summary.wall_time_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return summary;
}

}  // namespace impactid
