// Which runs the batched kernels take, and which share a batch: level-independent, so compiled
// once (the kernels themselves are compiled per level: core/batch/kernel_target.hpp). Declared in
// core/batch/batched_simulation.hpp, core/batch/batched_explicit.hpp,
// core/batch/batched_kr_alpha.hpp, core/batch/batched_chain.hpp and core/batch/batched_model.hpp
// beside the kernels they describe.
#include <cstring>
#include <variant>

#include "core/algebra/contact_lcp.hpp"
#include "core/batch/batch_kernels.hpp"
#include "core/batch/batched_chain.hpp"
#include "core/batch/batched_explicit.hpp"
#include "core/batch/batched_kr_alpha.hpp"
#include "core/batch/batched_model.hpp"
#include "core/batch/batched_simulation.hpp"
#include "core/contact/contact_law_registry.hpp"
#include "core/methods/stepper_coefficients.hpp"

namespace impactid {
namespace {

bool same_tridiagonal(const Tridiagonal& a, const Tridiagonal& b) {
  return a.lower == b.lower && a.diag == b.diag && a.upper == b.upper;
}

// The same stored entries, bit for bit (a NaN equals itself): the matrices' pattern and values.
bool same_sparse(const SparseMatrix& a, const SparseMatrix& b) {
  if (a.rows() != b.rows() || a.cols() != b.cols() || a.nonZeros() != b.nonZeros() ||
      !a.isCompressed() || !b.isCompressed()) {
    return false;
  }
  const auto same = [](const auto* x, const auto* y, Eigen::Index count) {
    return count == 0 || std::memcmp(x, y, sizeof(*x) * static_cast<std::size_t>(count)) == 0;
  };
  return same(a.outerIndexPtr(), b.outerIndexPtr(), a.outerSize() + 1) &&
         same(a.innerIndexPtr(), b.innerIndexPtr(), a.nonZeros()) &&
         same(a.valuePtr(), b.valuePtr(), a.nonZeros());
}

bool same_options(const RunOptions& a, const RunOptions& b) {
  return a.energy_growth_limit == b.energy_growth_limit &&
         a.energy_check_interval == b.energy_check_interval &&
         a.record_history == b.record_history && a.skip_free_flight == b.skip_free_flight;
}

// The rod's kernels enforce Lagrange's law; central difference's also a two-step gap's
// (Paoli–Schatzman's: core/batch/cdm_kernel.hpp shifts the gap as the scalar step does).
bool rod_kernel_law(const RunOptions& options, const MethodParams& method) {
  return options.contact.law == lagrange_law().law ||
         (descriptor(options.contact.law).two_step_gap &&
          explicit_batch_kind(method) == ExplicitBatchKind::central_difference);
}

// The restitution a rod kernel's batch steps with (one per batch): the law's if it has a two-step
// gap, else none whatever the field holds.
double kernel_restitution(const RunOptions& options) {
  return descriptor(options.contact.law).two_step_gap ? options.contact.restitution : 0.0;
}

}  // namespace

bool batchable(const RodScene& scene, const MethodParams& method, const RunOptions& options) {
  // Fields the kernel does not know make a scene unbatchable (simulate() runs it): here the far
  // wall. A new RodScene field belongs in this check or in same_batch. The kernel steps the
  // single-step implicit family, the composite schemes, Wilson-θ and Houbolt, and (
  // core/batch/batched_explicit.hpp) the explicit methods it knows, and KR-α
  // (core/batch/batched_kr_alpha.hpp), with Lagrange multipliers (not the penalty or
  // augmented-Lagrangian contact laws).
  return (is_single_step_implicit(method) || is_composite(method) ||
          stepped_by<WilsonThetaCoefficients>(method) || stepped_by<HouboltCoefficients>(method) ||
          explicit_batchable(scene, method) || kr_alpha_batchable(scene, method)) &&
         !scene.far_gap && !options.record_history && rod_kernel_law(options, method) &&
         // The kernels' steps assume a regular mass: a modified mass's massless contact DOF
         // (redistributed, singular) runs through simulate().
         !has_massless_dofs(scene.mass);
}

bool same_batch(const RodScene& a, const MethodParams& method_a, const RunOptions& options_a,
                const RodScene& b, const MethodParams& method_b, const RunOptions& options_b) {
  // A batch steps one kind of step: the single-step family's, the composite schemes',
  // Wilson-θ's or Houbolt's (each lane its own method and parameters within it, γ and θ too).
  if (batch_step_kind(method_a) != batch_step_kind(method_b)) return false;
  // An explicit method's batch (core/batch/batched_explicit.hpp) steps that method only.
  if (explicit_batch_kind(method_a) != explicit_batch_kind(method_b)) return false;
  // So does KR-α's (core/batch/batched_kr_alpha.hpp).
  if (stepped_by<KrAlphaCoefficients>(method_a) != stepped_by<KrAlphaCoefficients>(method_b)) {
    return false;
  }
  // The rod's matrices (assemble_rod) and the time step must agree; gap, velocity and t_end
  // are per lane.
  const bool same_rod =
      a.length == b.length && a.elements == b.elements && a.youngs_modulus == b.youngs_modulus &&
      a.density == b.density && a.area == b.area && a.mass == b.mass &&
      a.rayleigh_mass == b.rayleigh_mass && a.rayleigh_stiffness == b.rayleigh_stiffness;
  const bool same_options = options_a.energy_growth_limit == options_b.energy_growth_limit &&
                            options_a.energy_check_interval == options_b.energy_check_interval &&
                            options_a.record_history == options_b.record_history &&
                            options_a.skip_free_flight == options_b.skip_free_flight &&
                            kernel_restitution(options_a) == kernel_restitution(options_b);
  return same_rod && same_options && derive(a).time_step == derive(b).time_step;
}

ExplicitBatchKind explicit_batch_kind(const MethodParams& method) {
  const StepperCoefficients stepper = stepper_coefficients(method);
  if (std::holds_alternative<CentralDifferenceCoefficients>(stepper)) {
    return ExplicitBatchKind::central_difference;
  }
  if (std::holds_alternative<NohBatheCoefficients>(stepper)) return ExplicitBatchKind::noh_bathe;
  if (std::holds_alternative<KimExplicitCoefficients>(stepper)) {
    return ExplicitBatchKind::kim_explicit;
  }
  return ExplicitBatchKind::none;
}

bool explicit_batchable(const RodScene& scene, const MethodParams& method) {
  switch (explicit_batch_kind(method)) {
    case ExplicitBatchKind::central_difference:
      // Damping adds terms to the step and to the left-hand matrix (per velocity variant) that
      // the kernel does not have: damped central difference runs through simulate().
      return scene.rayleigh_mass == 0.0 && scene.rayleigh_stiffness == 0.0;
    case ExplicitBatchKind::noh_bathe:
      // Damping adds a product with C to each sub-step: damped runs go through simulate().
      return scene.rayleigh_mass == 0.0 && scene.rayleigh_stiffness == 0.0;
    case ExplicitBatchKind::kim_explicit:
      // Likewise a product with C to each stage.
      return scene.rayleigh_mass == 0.0 && scene.rayleigh_stiffness == 0.0;
    case ExplicitBatchKind::none:
      return false;
  }
  return false;
}

bool kr_alpha_batchable(const RodScene& scene, const MethodParams& method) {
  // Damping adds a product with C to each half of the right-hand side: damped runs go through
  // simulate().
  return stepped_by<KrAlphaCoefficients>(method) && scene.rayleigh_mass == 0.0 &&
         scene.rayleigh_stiffness == 0.0;
}

bool chain_batchable(const AssembledScene& scene, const MethodParams& method,
                     const RunOptions& options) {
  const SecondOrderSystem& system = scene.system;
  // A clamped end, an initial displacement or gravity (AssembledScene::starts_free false) runs
  // through simulate(): the kernel's lanes have not been held bit for bit to it on such a scene
  // (tests/batched_chain_test.cpp covers bodies that start free and unstrained), and its step has
  // no load term.
  if (!scene.starts_free || scene.system.load.active() || has_massless_dofs(scene.mass)) {
    return false;  // nor a modified mass's massless contact nodes
  }
  if (!is_single_step_implicit(method) || options.record_history ||
      options.contact.law != lagrange_law().law || !system.has_constraint_list() ||
      system.has_contact() || system.has_far_contact() || !scene.contact_columns ||
      system.size() < 3 || scene.probes.size() != system.constraints.size() ||
      system.constraints.size() > static_cast<std::size_t>(kMaxConstraints)) {
    return false;
  }
  // A wall's node is put on the wall at the end of a step: the kernel keeps the first and the
  // last row's state plain for that (the others are deferred).
  const Eigen::Index last = system.size() - 1;
  for (const Constraint& c : system.constraints) {
    if (c.plus < 0 && c.minus != 0) return false;
    if (c.minus < 0 && c.plus != last) return false;
  }
  return true;
}

bool same_chain_batch(const AssembledScene& a, const RunOptions& options_a, const AssembledScene& b,
                      const RunOptions& options_b) {
  const SecondOrderSystem& s = a.system;
  const SecondOrderSystem& t = b.system;
  if (s.size() != t.size() || s.constraints.size() != t.constraints.size() ||
      a.probes.size() != b.probes.size()) {
    return false;
  }
  for (std::size_t k = 0; k < s.constraints.size(); ++k) {
    if (s.constraints[k].plus != t.constraints[k].plus ||
        s.constraints[k].minus != t.constraints[k].minus || a.probes[k].area != b.probes[k].area ||
        a.probes[k].velocity_dof != b.probes[k].velocity_dof) {
      return false;
    }
  }
  const bool same_options = options_a.energy_growth_limit == options_b.energy_growth_limit &&
                            options_a.energy_check_interval == options_b.energy_check_interval &&
                            options_a.record_history == options_b.record_history &&
                            options_a.skip_free_flight == options_b.skip_free_flight;
  return same_options && a.dt == b.dt && a.rigid_flight == b.rigid_flight &&
         same_tridiagonal(s.mass, t.mass) && same_tridiagonal(s.stiffness, t.stiffness) &&
         same_tridiagonal(s.damping, t.damping);
}

bool model_kernel_method(const MethodParams& method) {
  const StepperCoefficients stepper = stepper_coefficients(method);
  const auto* cdm = std::get_if<CentralDifferenceCoefficients>(&stepper);
  return cdm && cdm->velocity == CdmVelocity::central;
}

bool model_batchable(const AssembledScene& scene, const MethodParams& method,
                     const RunOptions& options) {
  // Damping adds a product with C to the step (and C/(2Δt) to the left-hand matrix), a load its
  // term, the penalty laws their springs or iterations, the backward velocity another finish:
  // those runs go through simulate().
  return scene.sparse && model_kernel_method(method) && !scene.sparse->has_damping() &&
         !scene.sparse->load.active() && !scene.sparse->constraints.empty() &&
         scene.probes.size() == scene.sparse->constraints.size() && scene.contact_columns &&
         !options.record_history && options.contact.law == lagrange_law().law;
}

bool same_model_batch(const AssembledScene& a, const RunOptions& options_a, const AssembledScene& b,
                      const RunOptions& options_b) {
  const SparseSystem& s = *a.sparse;
  const SparseSystem& t = *b.sparse;
  if (s.constraints.size() != t.constraints.size() || a.probes.size() != b.probes.size()) {
    return false;
  }
  for (std::size_t k = 0; k < s.constraints.size(); ++k) {
    const Constraint &c = s.constraints[k], &d = t.constraints[k];
    if (c.plus != d.plus || c.minus != d.minus || c.gap != d.gap ||
        a.probes[k].area != b.probes[k].area ||
        a.probes[k].velocity_dof != b.probes[k].velocity_dof) {
      return false;
    }
  }
  return same_options(options_a, options_b) && a.rigid_flight == b.rigid_flight &&
         a.initial_velocity.size() == b.initial_velocity.size() &&
         a.initial_velocity == b.initial_velocity &&
         a.initial_displacement.size() == b.initial_displacement.size() &&
         a.initial_displacement == b.initial_displacement && same_sparse(s.mass, t.mass) &&
         same_sparse(s.stiffness, t.stiffness);
}

}  // namespace impactid
