// The paper's 1D impact scene: a linearly elastic rod of 2-node truss elements moving toward a
// rigid wall (Serfőző & Pere 2022, sec. 3, Figs 1–2, doi:10.1556/606.2022.00599).
//
// Units: N, mm, s, t (tonne); stress and E in MPa = N/mm², density in t/mm³.
// Conventions: nodes 0..n, node n is the contact node (the wall end); the wall stands at
// x = L + gap; the constraint is u_n <= gap; positive velocity points toward the wall; the
// contact pressure is p = λ/A >= 0.
//
// Optional second wall (the repeated-impact scene of issue 5): with far_gap set, a rigid wall
// also stands behind the rod at x = −far_gap, the constraint u_0 >= −far_gap holds at node 0
// with its own multiplier λ_0 >= 0, and the rod bounces between the two walls. Without it the
// scene is exactly the paper's.
#pragma once

#include <optional>
#include <string>

#include "core/common/parameter_error.hpp"

namespace impactid {

/// The mass treatment (plan and CLI key `mass`). The last two are the modified masses of the
/// contact literature: the contact node (the node at the wall, and node 0 too with a far wall)
/// carries no mass, so that its equation is static within each step and the contact pressure
/// loses the spurious oscillation the node's own inertia drives. Their matrices, and why
/// (assembled in core/model/second_order_system.cpp: apply_contact_mass):
///   redistributed  the lumped mass with the contact node's ρAh/2 moved onto its neighbour (which
///                  then holds 3ρAh/2): Khenous, Laborde & Renard 2008, "Mass redistribution
///                  method for finite element contact problems in elastodynamics", Eur. J. Mech.
///                  A/Solids 27. Total mass kept, diagonal.
///   singular       the consistent mass with the contact node's row and column removed and the
///                  neighbour's diagonal set to 7ρAh/12: the singular dynamic mass of Renard 2010
///                  ("The singular dynamic method for constrained second order hyperbolic
///                  equations", J. Comput. Appl. Math. 234) as GetFEM's
///                  demo_dynamic_contact_1D builds it for P1 (mass_matrix_type = 2). 7h/12 =
///                  h/3 + h/4: the neighbour keeps its consistent h/3 from the inner element, and
///                  the contact element's kinetic energy is taken at its midpoint (one-point
///                  Gauss rule, exact for constants) with the contact node's velocity left out,
///                  ½·ρAh·(v_nb/2)². It is not mass-preserving: the contact element weighs ρAh/4
///                  instead of ρAh, 3ρAh/4 lost, which vanishes with h.
/// A massless DOF is taken only by methods that say how they step it
/// (core/methods/method_registry.hpp: MethodDescriptor::massless_dofs).
enum class MassMatrix {
  lumped,      ///< row-sum lumped (ρAh/2 at each node of an element); the default for every method
  consistent,  ///< ρAh/6·[2 1; 1 2] per element
  redistributed,  ///< lumped, the contact node's mass moved onto its neighbour (above)
  singular,       ///< consistent, the contact node massless, its neighbour's diagonal 7ρAh/12
};
const char* to_string(MassMatrix kind);
std::optional<MassMatrix> mass_matrix_from_string(const std::string& name);
/// Every mass treatment's name, as "lumped|consistent|redistributed|singular".
const char* mass_matrix_names();
/// One line on the treatment, for `impactid methods`.
const char* mass_matrix_description(MassMatrix kind);
/// Every treatment, in the order of mass_matrix_names().
inline constexpr MassMatrix kMassMatrices[] = {MassMatrix::lumped, MassMatrix::consistent,
                                               MassMatrix::redistributed, MassMatrix::singular};
/// Whether the treatment leaves the contact DOFs without mass (redistributed, singular).
bool has_massless_dofs(MassMatrix kind);

/// Every parameter of the scene, with the defaults that reproduce the paper's qualitative
/// results. The paper leaves gap, area, time step and end time unstated; they are chosen here.
struct RodScene {
  double length = 20.0;          ///< L [mm], > 0
  int elements = 200;            ///< n, >= 1; h = L/n
  double youngs_modulus = 90.0;  ///< E [MPa], > 0
  double density = 7.85e-9;      ///< ρ [t/mm³], > 0
  double area = 1.0;             ///< A [mm²], > 0
  double velocity = 1000.0;      ///< v0 [mm/s], toward the wall, finite
  double gap = 0.01;             ///< initial gap to the wall [mm], >= 0; 0.01 mm puts the impact
                                 ///< between two steps at the default Courant number
  /// Gap between node 0 and a second rigid wall behind the rod [mm], >= 0 and finite: the wall
  /// stands at x = −far_gap and node 0 may not move below it (u_0 >= −far_gap). Not set (the
  /// default): no second wall, the paper's scene.
  std::optional<double> far_gap;
  MassMatrix mass = MassMatrix::lumped;
  double rayleigh_mass = 0.0;       ///< a0 in C = a0·M + a1·K [1/s], >= 0
  double rayleigh_stiffness = 0.0;  ///< a1 in C = a0·M + a1·K [s], >= 0

  /// Courant number c·Δt/h with c = √(E/ρ); used when dt is not given. > 0.
  double courant = 0.5;
  /// Time step Δt [s]; when given it overrides courant.
  std::optional<double> dt;
  /// End time [s]; default t_impact + 1.5·(2L/c), i.e. the whole contact and half as long again.
  std::optional<double> t_end;

  bool operator==(const RodScene&) const = default;
};

/// First invalid field, or nothing.
std::optional<ParameterError> validate(const RodScene& scene);

/// N = ⌈t_end/Δt − 1e-9⌉ samples t_i = i·Δt, i = 1..N (at least 1; saturated rather than
/// undefined for absurd inputs, which validate() then rejects).
long step_count(double end_time, double time_step);

/// The most bytes a run's samples may take (8 GB): the rod's 1e8 steps stay below it.
inline constexpr double kMaxTraceBytes = 8e9;

/// The bounds every scene's time grid must meet (at most 1e8 steps, samples of its `contacts`
/// within kMaxTraceBytes, Δt <= t_end, Δt² a normal double), reported at `step_field` (dt or
/// courant) with its value; `default_end_note` explains a default t_end in the message ("" when
/// t_end was given).
std::optional<ParameterError> validate_time_grid(const std::string& step_field, double step_value,
                                                 double time_step, double end_time,
                                                 const std::string& default_end_note,
                                                 int contacts = 1);

/// Quantities derived from a valid scene, computed in one place.
struct RodSceneDerived {
  double wave_speed;        ///< c = √(E/ρ) [mm/s]
  double element_length;    ///< h = L/n [mm]
  double time_step;         ///< Δt [s]
  double impact_time;       ///< t_impact = gap/v0 [s] (+inf if v0 <= 0)
  double contact_duration;  ///< 2L/c [s], the exact length of the contact
  double end_time;          ///< t_end [s]
  long step_count;          ///< N = ⌈t_end/Δt − 1e-9⌉; samples are t_i = i·Δt, i = 1..N
  double pressure_scale;    ///< ρ·c·v0 [MPa], the exact contact pressure
  double initial_energy;    ///< ½·ρ·A·L·v0² [mJ = N·mm]
};
RodSceneDerived derive(const RodScene& scene);

}  // namespace impactid
