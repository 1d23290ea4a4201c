#include "core/reference/scene_reference.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>

#include "core/methods/method_registry.hpp"
#include "core/model/scene_assembly.hpp"
#include "core/reference/chain_exact.hpp"

namespace impactid {

double relative_change(const std::vector<double>& a, const std::vector<double>& b) {
  double difference = 0.0, size = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    difference += std::abs(a[i] - b[i]);
    size += std::abs(a[i]);
  }
  return size > 0.0 ? difference / size : (difference > 0.0 ? 1.0 : 0.0);
}

namespace {

// The samples of `scene` run with every segment's elements multiplied and its step divided by
// 2^k (the same Courant number), at the unrefined samples t_i.
bool refined_samples(const Scene& scene, const SceneDerived& derived, int k,
                     const ReferenceOptions& options, const ReferenceRun& run,
                     std::vector<ContactSamples>& out, std::string& message) {
  const long factor = 1L << k;
  Scene refined = scene;
  for (Body& body : refined.bodies) {
    for (Segment& segment : body.segments) segment.elements *= static_cast<int>(factor);
  }
  refined.dt = derived.time_step / static_cast<double>(factor);
  // The unrefined grid's last sample, so that the refined grid has exactly N·2^k steps.
  refined.t_end = static_cast<double>(derived.step_count) * derived.time_step;
  const AssembledScene assembled = assemble(refined);
  ContactTrace trace;
  const RunSummary summary = run(assembled, options.method, trace);
  if (summary.status != RunStatus::ok) {
    message = "the reference run at h/" + std::to_string(factor) + ", dt/" +
              std::to_string(factor) + " is " + to_string(summary.status) + ": " + summary.message;
    return false;
  }
  out.assign(trace.contact_pressure.size(), {});
  for (std::size_t c = 0; c < out.size(); ++c) {
    for (long i = 1; i <= derived.step_count; ++i) {
      const auto j = static_cast<std::size_t>(i * factor - 1);
      out[c].pressure.push_back(trace.contact_pressure[c][j]);
      out[c].velocity.push_back(trace.contact_velocity[c][j]);
    }
  }
  return true;
}

}  // namespace

bool operator==(const ReferenceOptions& a, const ReferenceOptions& b) {
  if (a.tolerance != b.tolerance || a.max_refinements != b.max_refinements) return false;
  return same_method_parameters(a.method, b.method);
}

std::optional<ClampedBarParams> clamped_bar_params(const Scene& scene) {
  if (scene.bodies.size() != 1 || scene.bodies[0].segments.size() != 1) return std::nullopt;
  const Body& body = scene.bodies[0];
  const Segment& segment = body.segments[0];
  const bool form = scene.left_wall && scene.left_wall->kind == WallKind::contact &&
                    scene.left_wall->gap == 0.0 && scene.right_wall &&
                    scene.right_wall->kind == WallKind::clamped && body.velocity == 0.0 &&
                    body.displacement.right == 0.0 && body.displacement.left > 0.0 &&
                    scene.rayleigh_mass == 0.0 && scene.rayleigh_stiffness == 0.0;
  if (!form) return std::nullopt;
  const ClampedBarParams params{.length = segment.length,
                                .youngs_modulus = segment.youngs_modulus,
                                .density = segment.density,
                                .amplitude = body.displacement.left};
  if (validate(params)) return std::nullopt;  // scales out of double's range
  return params;
}

std::optional<BouncingBarParams> bouncing_bar_params(const Scene& scene) {
  if (scene.bodies.size() != 1 || scene.bodies[0].segments.size() != 1) return std::nullopt;
  const Body& body = scene.bodies[0];
  const Segment& segment = body.segments[0];
  const bool form = scene.gravity < 0.0 && scene.left_wall &&
                    scene.left_wall->kind == WallKind::contact && !scene.right_wall &&
                    body.velocity == 0.0 && body.displacement.is_zero() &&
                    scene.rayleigh_mass == 0.0 && scene.rayleigh_stiffness == 0.0;
  if (!form) return std::nullopt;
  const BouncingBarParams params{.length = segment.length,
                                 .youngs_modulus = segment.youngs_modulus,
                                 .density = segment.density,
                                 .gravity = -scene.gravity};
  if (validate(params)) return std::nullopt;  // scales out of double's range
  const double drop = BouncingBarExact(params).initial_gap();
  if (!(std::abs(scene.left_wall->gap - drop) <= 1e-9 * drop)) return std::nullopt;
  return params;
}

std::string SceneReference::description() const {
  if (refinements == 0 && exact == SceneExact::clamped_bar) {
    return "exact solution of the clamped bar (core/reference/clamped_bar_exact.hpp)";
  }
  if (refinements == 0 && exact == SceneExact::bouncing_bar) {
    return "exact solution of the bouncing bar (core/reference/bouncing_bar_exact.hpp)";
  }
  if (refinements == 0) return "exact solution of the chain (core/reference/chain_exact.hpp)";
  return std::string(converged ? "converged" : "not converged") + ": " +
         to_string(kind_of(options.method)) + " at h/" + std::to_string(1L << refinements) +
         " and dt/" + std::to_string(1L << refinements) + ", relative change " +
         format_value(change) + " at the last halving (tolerance " +
         format_value(options.tolerance) + ")" + (message.empty() ? "" : "; " + message);
}

SceneReference scene_reference(const Scene& scene, const ReferenceOptions& options,
                               const ReferenceRun& run) {
  const SceneDerived derived = derive(scene);
  SceneReference r;
  r.scene = scene;
  r.options = options;
  const double dt = derived.time_step;
  // The two bars' one contact is the left wall's, with the same signs as the solution's contact
  // end; sampled by the convention of RodImpactExact::at_sample: jumps within 1e-6·Δt averaged.
  const auto sample_bar = [&](const auto& exact, SceneExact which) {
    r.exact = which;
    r.contacts.resize(1);
    ContactSamples& s = r.contacts[0];
    for (long i = 1; i <= derived.step_count; ++i) {
      const ContactNodeValues e = exact.at(static_cast<double>(i) * dt, 1e-6 * dt);
      s.pressure.push_back(e.pressure);
      s.velocity.push_back(e.velocity);
    }
  };
  if (const std::optional<ClampedBarParams> bar = clamped_bar_params(scene)) {
    sample_bar(ClampedBarExact(*bar), SceneExact::clamped_bar);
    return r;
  }
  if (const std::optional<BouncingBarParams> bar = bouncing_bar_params(scene)) {
    sample_bar(BouncingBarExact(*bar), SceneExact::bouncing_bar);
    return r;
  }
  if (scene.rayleigh_mass == 0.0 && scene.rayleigh_stiffness == 0.0 && bodies_start_free(scene)) {
    r.exact = SceneExact::chain;
    std::optional<ChainExact> solved;
    try {
      solved.emplace(scene, static_cast<double>(derived.step_count) * dt);
    } catch (const std::runtime_error& e) {  // more events than the solver allows
      r.converged = false;
      r.message = e.what();
      return r;
    }
    const ChainExact& exact = *solved;
    r.contacts.resize(static_cast<std::size_t>(exact.contact_count()));
    for (int c = 0; c < exact.contact_count(); ++c) {
      ContactSamples& s = r.contacts[static_cast<std::size_t>(c)];
      for (long i = 1; i <= derived.step_count; ++i) {
        // The sampling convention of RodImpactExact::at_sample: jumps within 1e-6·Δt averaged.
        const ContactNodeValues e = exact.at(c, static_cast<double>(i) * dt, 1e-6 * dt);
        s.pressure.push_back(e.pressure);
        s.velocity.push_back(e.velocity);
      }
    }
    return r;
  }
  const auto primary = static_cast<std::size_t>(derived.primary_contact);
  std::vector<ContactSamples> previous;
  if (!refined_samples(scene, derived, 1, options, run, previous, r.message)) {
    r.converged = false;
    r.refinements = 1;
    return r;
  }
  r.contacts = previous;
  r.refinements = 1;
  r.converged = false;
  for (int k = 2; k <= options.max_refinements; ++k) {
    std::vector<ContactSamples> next;
    if (!refined_samples(scene, derived, k, options, run, next, r.message)) return r;
    r.change = std::max(relative_change(next[primary].pressure, previous[primary].pressure),
                        relative_change(next[primary].velocity, previous[primary].velocity));
    r.contacts = next;
    r.refinements = k;
    if (r.change < options.tolerance) {
      r.converged = true;
      return r;
    }
    previous = std::move(next);
  }
  r.message = "the tolerance was not reached in " + std::to_string(options.max_refinements) +
              " halvings of the mesh and the step";
  return r;
}

}  // namespace impactid
