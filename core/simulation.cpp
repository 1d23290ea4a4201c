#include "core/simulation.hpp"

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

void reset_trace(ContactTrace& trace, long samples) {
  constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  for (auto* series : {&trace.pressure, &trace.velocity, &trace.displacement, &trace.energy}) {
    series->assign(static_cast<std::size_t>(samples), nan);
  }
}

// The step loop shared by every method. `advance` produces the state at the next sample time;
// it is a lambda, so the call is inlined: no virtual dispatch inside the loop.
template <class Advance>
void run_steps(const SecondOrderSystem& system, double area, const RunOptions& options,
               State& state, ContactTrace& trace, RunSummary& summary, Advance&& advance) {
  const Eigen::Index c = system.contact_dof;
  const double energy_bound = options.energy_growth_limit * summary.initial_energy;
  for (long i = 0; i < summary.planned_steps; ++i) {
    advance(state);
    const double energy = system.energy(state.u, state.v);
    trace.pressure[i] = state.lambda / area;
    trace.velocity[i] = state.v[c];
    trace.displacement[i] = state.u[c];
    trace.energy[i] = energy;
    summary.steps = i + 1;
    summary.final_energy = energy;
    if (!std::isfinite(energy) || !std::isfinite(state.lambda)) {
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
}

}  // namespace

RunSummary simulate(const RodScene& scene, const MethodParams& method, const RunOptions& options,
                    SimulationWorkspace& ws) {
  const auto start = std::chrono::steady_clock::now();
  const RodSceneDerived derived = derive(scene);
  const SecondOrderSystem system = assemble_rod(scene);
  const Eigen::Index n = system.size();

  RunSummary summary;
  summary.planned_steps = derived.step_count;
  summary.dt = derived.time_step;
  reset_trace(ws.trace, derived.step_count);

  State& state = ws.state;
  state.u.setZero(n);
  state.v.setConstant(n, scene.velocity);
  state.lambda = 0.0;
  state.t = 0.0;
  state.a = consistent_acceleration(system, state);  // zero without damping
  summary.initial_energy = system.energy(state.u, state.v);
  summary.final_energy = summary.initial_energy;

  const double dt = derived.time_step;
  if (const auto* cdm = std::get_if<CentralDifferenceParams>(&method)) {
    CentralDifference& stepper = ws.central_difference;
    if (stepper.initialize(system, cdm->velocity, dt, state)) {
      stepper.step(system, state);  // the state at t = 0 is not a sample
      run_steps(system, scene.area, options, state, ws.trace, summary,
                [&](State& s) { stepper.step(system, s); });
    } else {
      summary.status = RunStatus::failed;
      summary.message = "central difference: singular left-hand matrix";
    }
  } else {
    ImplicitIntegrator& stepper = ws.implicit;
    if (stepper.initialize(system, implicit_coefficients(method), dt)) {
      run_steps(system, scene.area, options, state, ws.trace, summary,
                [&](State& s) { stepper.step(system, s); });
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
