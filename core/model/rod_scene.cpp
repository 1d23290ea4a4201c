#include "core/model/rod_scene.hpp"

#include <cmath>
#include <limits>
#include <string>

namespace impactid {

const char* to_string(MassMatrix kind) {
  switch (kind) {
    case MassMatrix::lumped:
      return "lumped";
    case MassMatrix::consistent:
      return "consistent";
    case MassMatrix::redistributed:
      return "redistributed";
    case MassMatrix::singular:
      return "singular";
  }
  return "unknown";
}

std::optional<MassMatrix> mass_matrix_from_string(const std::string& name) {
  for (MassMatrix kind : kMassMatrices) {
    if (name == to_string(kind)) return kind;
  }
  return std::nullopt;
}

const char* mass_matrix_description(MassMatrix kind) {
  switch (kind) {
    case MassMatrix::lumped:
      return "row-sum lumped, rho*A*h/2 at each node of an element (the default)";
    case MassMatrix::consistent:
      return "consistent, rho*A*h/6*[2 1; 1 2] per element";
    case MassMatrix::redistributed:
      return "lumped with the contact node's mass moved onto its neighbour: the contact node "
             "massless, total mass kept (Khenous, Laborde & Renard 2008); the rod only";
    case MassMatrix::singular:
      return "consistent with the contact node's row and column removed and its neighbour's "
             "diagonal 7*rho*A*h/12 (Renard 2010's singular dynamic mass, as GetFEM builds it "
             "for P1); 3*rho*A*h/4 of mass lost; the rod only";
  }
  return "";
}

const char* mass_matrix_names() {
  return "lumped|consistent|redistributed|singular";
}

bool has_massless_dofs(MassMatrix kind) {
  return kind == MassMatrix::redistributed || kind == MassMatrix::singular;
}

long step_count(double end_time, double time_step) {
  // Converted with care: validate() derives a scene before it rejects absurd inputs, and casting
  // an out-of-range (or NaN) double to long is undefined behaviour.
  const double steps = std::ceil(end_time / time_step - 1e-9);
  if (!(steps >= 1.0)) return 1;
  if (steps < 9.0e18) return static_cast<long>(steps);
  return std::numeric_limits<long>::max();
}

std::optional<ParameterError> validate_time_grid(const std::string& step_field, double step_value,
                                                 double time_step, double end_time,
                                                 const std::string& default_end_note,
                                                 int contacts) {
  const std::string value = format_value(step_value);
  // Runs beyond 1e8 steps are mistakes in the inputs, not simulations to attempt: the trace holds 2
  // doubles per step per contact (4 with histories), and such a run takes many minutes even on the
  // default scene.
  if (!(end_time / time_step < 1e8)) {
    std::string why =
        "gives more than 1e8 time steps up to t_end = " + format_value(end_time) + " s";
    if (!default_end_note.empty()) why += " (" + default_end_note + "; give t_end)";
    return ParameterError{step_field, value, why};
  }
  // The samples are kept in memory for the indicators: per step the primary contact's four
  // values (pressure, velocity, and with histories displacement and energy) and every contact's
  // pressure and velocity. A scene with many contacts reaches the memory of a machine long before
  // 1e8 steps, so the bound is on the bytes too, checked before anything is allocated.
  const double bytes = std::ceil(end_time / time_step) * 8.0 * (4.0 + 2.0 * contacts);
  if (bytes > kMaxTraceBytes) {
    return ParameterError{step_field, value,
                          "gives " + format_value(std::ceil(end_time / time_step)) +
                              " time steps up to t_end = " + format_value(end_time) + " s, whose " +
                              std::to_string(contacts) + " contacts' samples would take " +
                              format_value(bytes / 1e9) + " GB, more than the " +
                              format_value(kMaxTraceBytes / 1e9) +
                              " GB a run may keep (a larger step or a shorter t_end)"};
  }
  // Every sample lies in (0, t_end + dt): with dt > t_end the only one would lie past t_end.
  if (time_step > end_time) {
    return ParameterError{step_field, value,
                          "gives dt = " + format_value(time_step) +
                              " s, longer than t_end = " + format_value(end_time) + " s"};
  }
  // The integrators compute dt^2 and 1/dt^2. Outside the normal range of double they underflow
  // or overflow, and a run would end `unstable` or `failed` for reasons that are not the
  // method's.
  const double dt2 = time_step * time_step;
  if (!std::isnormal(dt2) || !std::isnormal(1.0 / dt2)) {
    return ParameterError{step_field, value,
                          "gives dt = " + format_value(time_step) +
                              " s, whose square is not a normal double (dt in [1.5e-154, "
                              "1.3e154] s)"};
  }
  return std::nullopt;
}

std::optional<ParameterError> validate(const RodScene& s) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  constexpr double tiny = std::numeric_limits<double>::min();
  if (s.elements < 1) {
    return ParameterError{"elements", std::to_string(s.elements), "must be a positive integer"};
  }
  for (auto error : {
           require_in_range("length", s.length, tiny, std::numeric_limits<double>::max(),
                            "must be positive and finite"),
           require_in_range("youngs_modulus", s.youngs_modulus, tiny,
                            std::numeric_limits<double>::max(), "must be positive and finite"),
           require_in_range("density", s.density, tiny, std::numeric_limits<double>::max(),
                            "must be positive and finite"),
           require_in_range("area", s.area, tiny, std::numeric_limits<double>::max(),
                            "must be positive and finite"),
           require_in_range("velocity", s.velocity, -std::numeric_limits<double>::max(),
                            std::numeric_limits<double>::max(), "must be finite"),
           require_in_range("gap", s.gap, 0.0, std::numeric_limits<double>::max(),
                            "must be >= 0 and finite"),
           require_in_range("rayleigh_mass", s.rayleigh_mass, 0.0,
                            std::numeric_limits<double>::max(), "must be >= 0 and finite"),
           require_in_range("rayleigh_stiffness", s.rayleigh_stiffness, 0.0,
                            std::numeric_limits<double>::max(), "must be >= 0 and finite"),
           require_in_range("courant", s.courant, tiny, std::numeric_limits<double>::max(),
                            "must be positive and finite"),
       }) {
    if (error) return error;
  }
  if (s.far_gap) {
    if (auto e = require_in_range("far_gap", *s.far_gap, 0.0, std::numeric_limits<double>::max(),
                                  "must be >= 0 and finite");
        e) {
      return e;
    }
  }
  if (s.dt) {
    if (auto e = require_in_range("dt", *s.dt, tiny, inf, "must be positive and finite"); e) {
      return e;
    }
    if (!std::isfinite(*s.dt)) return ParameterError{"dt", format_value(*s.dt), "must be finite"};
  }
  if (s.t_end) {
    if (!(std::isfinite(*s.t_end) && *s.t_end > 0.0)) {
      return ParameterError{"t_end", format_value(*s.t_end), "must be positive and finite"};
    }
  }
  // More elements are a mistake in the input, not a simulation to attempt: the workspace holds
  // ~20 doubles per node, so the bound keeps a run within a few GB of memory (and the time
  // grid's bounds are validate_time_grid's).
  constexpr long max_elements = 10'000'000;
  if (s.elements > max_elements) {
    return ParameterError{"elements", std::to_string(s.elements), "must be at most 1e7"};
  }
  // With two walls and one element both nodes would be contact nodes, and a modified mass would
  // leave the rod without any.
  if (has_massless_dofs(s.mass) && s.far_gap && s.elements < 2) {
    return ParameterError{"mass", to_string(s.mass),
                          "needs at least 2 elements with a far wall (both nodes of a single "
                          "element would be massless contact nodes)"};
  }
  const RodSceneDerived d = derive(s);
  if (auto e = validate_time_grid(
          s.dt ? "dt" : "courant", s.dt ? *s.dt : s.courant, d.time_step, d.end_time,
          s.t_end ? "" : "the default t_end follows the impact at gap/v0")) {
    return e;
  }
  if (s.velocity != 0.0 &&
      !(std::isnormal(d.initial_energy) && std::isnormal(s.velocity * s.velocity))) {
    return ParameterError{
        "velocity", format_value(s.velocity),
        "gives an initial energy 1/2*rho*A*L*v0^2 = " + format_value(d.initial_energy) +
            " mJ outside the normal range of double"};
  }
  return std::nullopt;
}

RodSceneDerived derive(const RodScene& s) {
  RodSceneDerived d{};
  d.wave_speed = std::sqrt(s.youngs_modulus / s.density);
  d.element_length = s.length / s.elements;
  d.time_step = s.dt ? *s.dt : s.courant * d.element_length / d.wave_speed;
  d.impact_time = s.velocity > 0.0 ? s.gap / s.velocity : std::numeric_limits<double>::infinity();
  d.contact_duration = 2.0 * s.length / d.wave_speed;
  if (s.t_end) {
    d.end_time = *s.t_end;
  } else {
    // Without an impact (v0 <= 0 and a gap) there is nothing to wait for: one contact duration.
    const double start = std::isfinite(d.impact_time) ? d.impact_time : 0.0;
    d.end_time = start + 1.5 * d.contact_duration;
  }
  d.step_count = step_count(d.end_time, d.time_step);
  d.pressure_scale = s.density * d.wave_speed * std::abs(s.velocity);
  d.initial_energy = 0.5 * s.density * s.area * s.length * s.velocity * s.velocity;
  return d;
}

}  // namespace impactid
