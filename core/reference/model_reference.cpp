#include "core/reference/model_reference.hpp"

#include <cmath>
#include <optional>

namespace impactid {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The history's values at t_i = i·Δt, i = 1..N: its own where a time matches to 1e-9·Δt, linear
// between two samples otherwise; NaN outside the history (reported by the caller).
std::vector<double> resample(const std::vector<double>& t, const std::vector<double>& x, double dt,
                             long n) {
  std::vector<double> out(static_cast<std::size_t>(n), kNaN);
  std::size_t j = 0;
  for (long i = 1; i <= n; ++i) {
    const double ti = static_cast<double>(i) * dt;
    while (j + 1 < t.size() && t[j + 1] <= ti + 1e-9 * dt) ++j;
    if (std::abs(t[j] - ti) <= 1e-9 * dt) {
      out[static_cast<std::size_t>(i - 1)] = x[j];
    } else if (t[j] < ti && j + 1 < t.size()) {
      const double w = (ti - t[j]) / (t[j + 1] - t[j]);
      out[static_cast<std::size_t>(i - 1)] = x[j] + w * (x[j + 1] - x[j]);
    }
  }
  return out;
}

// The samples of `scene` run by the reference method at Δt/2^k, at the run's samples t_i: each
// the mean of the refined samples in the window (t_i − Δt/2, t_i + Δt/2] (why: see the header).
// The refined run goes on half a step past the last sample to fill its window.
bool refined_samples(const AssembledScene& scene, int k, const ReferenceOptions& options,
                     const ReferenceRun& run, std::vector<ContactSamples>& out,
                     std::string& message) {
  const long factor = 1L << k;
  AssembledScene refined = scene;
  refined.dt = scene.dt / static_cast<double>(factor);
  refined.step_count = scene.step_count * factor + factor / 2;
  ContactTrace trace;
  const RunSummary summary = run(refined, options.method, trace);
  if (summary.status != RunStatus::ok) {
    message = "the reference run at dt/" + std::to_string(factor) + " is " +
              to_string(summary.status) + ": " + summary.message;
    return false;
  }
  out.assign(trace.contact_pressure.size(), {});
  for (std::size_t c = 0; c < out.size(); ++c) {
    const std::vector<double>& pressure = trace.contact_pressure[c];
    const std::vector<double>& velocity = trace.contact_velocity[c];
    for (long i = 1; i <= scene.step_count; ++i) {
      // Refined sample j (index j − 1) is at t = j·Δt/2^k.
      double p = 0.0, v = 0.0;
      for (long j = i * factor - factor / 2 + 1; j <= i * factor + factor / 2; ++j) {
        p += pressure[static_cast<std::size_t>(j - 1)];
        v += velocity[static_cast<std::size_t>(j - 1)];
      }
      out[c].pressure.push_back(p / static_cast<double>(factor));
      out[c].velocity.push_back(v / static_cast<double>(factor));
    }
  }
  return true;
}

// A converged solution by one method: the run refined until the primary contact's change is
// below the tolerance, or the last one computed.
struct Refinement {
  std::vector<ContactSamples> contacts;  ///< empty when every halving failed
  int refinements = 0;
  double dt = 0.0;
  double change = kNaN;
  bool converged = false;
  std::string message;
};

Refinement refine(const AssembledScene& assembled, const ReferenceOptions& options,
                  const ReferenceRun& run, std::size_t p) {
  Refinement r;
  // A halving whose run is not ok (central difference above its stability limit at the first
  // halvings) is passed over until one is; after that, a failed run ends the refinement.
  std::optional<std::vector<ContactSamples>> previous;
  for (int k = 1; k <= options.max_refinements; ++k) {
    std::vector<ContactSamples> next;
    if (!refined_samples(assembled, k, options, run, next, r.message)) {
      if (previous) return r;
      continue;
    }
    r.message.clear();
    r.refinements = k;
    r.dt = assembled.dt / static_cast<double>(1L << k);
    if (previous) {
      r.change = std::max(relative_change(next[p].pressure, (*previous)[p].pressure),
                          relative_change(next[p].velocity, (*previous)[p].velocity));
    }
    r.contacts = next;
    if (previous && r.change < options.tolerance) {
      r.converged = true;
      return r;
    }
    previous = std::move(next);
  }
  if (r.contacts.empty()) {
    r.refinements = options.max_refinements;
    return r;  // every halving failed: the last one's message says why
  }
  r.message = "the tolerance was not reached in " + std::to_string(options.max_refinements) +
              " halvings of the step";
  return r;
}

}  // namespace

bool ModelReference::trusted() const {
  if (refinements < 0) return converged;  // a supplied history that covers the run
  return converged && has_check && check_converged;
}

CheckMethod check_method_for(const MethodParams& method, const Model& model) {
  if (kind_of(method) != MethodKind::backward_euler) {
    return {default_params(MethodKind::backward_euler), 1};
  }
  if (is_diagonal(model.mass)) return {CentralDifferenceParams{}, 2};
  return {HhtParams{.alpha = -0.3}, 2};
}

bool ModelReference::usable(int primary) const {
  const auto k = static_cast<std::size_t>(primary);
  return k < contacts.size() && !contacts[k].pressure.empty() && !contacts[k].velocity.empty();
}

std::string ModelReference::description() const {
  if (refinements < 0) {
    return "supplied: " + scene.model->reference->source + (message.empty() ? "" : "; " + message);
  }
  const char* state = !converged ? "not converged" : trusted() ? "converged" : "not verified";
  return std::string(state) + ": " + to_string(kind_of(options.method)) + " at dt/" +
         std::to_string(1L << refinements) + " = " + format_value(dt) + ", relative change " +
         format_value(change) + " at the last halving (tolerance " +
         format_value(options.tolerance) + ")" + check_text() +
         (message.empty() ? "" : "; " + message);
}

std::string ModelReference::check_text() const {
  if (!has_check) return "";
  return "; checked by " + std::string(to_string(kind_of(check_method))) + " at dt/" +
         std::to_string(1L << check_refinements) + ", extrapolated: difference " +
         format_value(disagreement) + " (at most " + format_value(agreement_tolerance()) +
         "), estimated error " + format_value(error);
}

ReferenceOptions model_reference_defaults(const Model& model) {
  ReferenceOptions options{
      .method = HhtParams{.alpha = -0.3}, .tolerance = 1e-3, .max_refinements = 10};
  if (is_diagonal(model.mass)) options.method = CentralDifferenceParams{};
  return options;
}

ModelReference model_reference(const ModelScene& scene, const ReferenceOptions& options,
                               const ReferenceRun& run) {
  ModelReference r;
  r.scene = scene;
  r.options = options;
  const AssembledScene assembled = assemble(scene);
  const Model& model = *scene.model;
  const int primary = primary_contact_index(scene);
  if (model.reference) {
    const ReferenceHistory& h = *model.reference;
    r.dt = kNaN;
    r.contacts.resize(model.contacts.size());
    const double last = static_cast<double>(assembled.step_count) * assembled.dt;
    if (h.t.front() > assembled.dt * (1.0 + 1e-9) || h.t.back() < last * (1.0 - 1e-12)) {
      r.converged = false;
      r.message = "the history covers t = " + format_value(h.t.front()) + " to " +
                  format_value(h.t.back()) + ", the run's samples " + format_value(assembled.dt) +
                  " to " + format_value(last);
      r.contacts.clear();
      return r;
    }
    for (std::size_t k = 0; k < model.contacts.size(); ++k) {
      if (h.contacts[k].pressure.empty() || h.contacts[k].velocity.empty()) continue;
      r.contacts[k].pressure =
          resample(h.t, h.contacts[k].pressure, assembled.dt, assembled.step_count);
      r.contacts[k].velocity =
          resample(h.t, h.contacts[k].velocity, assembled.dt, assembled.step_count);
    }
    if (!r.usable(primary)) {
      r.converged = false;
      r.message = "the history has no pressure and velocity of the primary contact " +
                  model.contacts[static_cast<std::size_t>(primary)].name;
    }
    return r;
  }
  const auto p = static_cast<std::size_t>(primary);
  const Refinement main = refine(assembled, options, run, p);
  r.contacts = main.contacts;
  r.refinements = main.refinements;
  r.dt = main.dt;
  r.change = main.change;
  r.converged = main.converged;
  r.message = main.message;
  if (!r.converged) return r;
  ReferenceOptions check_options = options;
  const CheckMethod check = check_method_for(options.method, model);
  check_options.method = check.method;
  r.has_check = true;
  r.check_method = check.method;
  // The check's runs at Δt/2^k, k = 1, 2, …, each after the second extrapolated (Richardson, by
  // the check method's order q: x_k + (x_k − x_{k−1})/(2^q − 1)) and compared with the
  // reference, until they agree within the agreement tolerance or the halvings run out.
  std::optional<std::vector<ContactSamples>> previous;
  std::string failure;
  for (int k = 1; k <= options.max_refinements; ++k) {
    std::vector<ContactSamples> next;
    if (!refined_samples(assembled, k, check_options, run, next, failure)) {
      if (previous) break;
      continue;
    }
    r.check_refinements = k;
    if (previous) {
      const double factor = 1.0 / static_cast<double>((1L << check.order) - 1);
      ContactSamples extrapolated = next[p];
      for (std::size_t i = 0; i < extrapolated.pressure.size(); ++i) {
        extrapolated.pressure[i] += factor * (next[p].pressure[i] - (*previous)[p].pressure[i]);
        extrapolated.velocity[i] += factor * (next[p].velocity[i] - (*previous)[p].velocity[i]);
      }
      r.check_change = std::max(relative_change(next[p].pressure, (*previous)[p].pressure),
                                relative_change(next[p].velocity, (*previous)[p].velocity));
      r.disagreement = std::max(relative_change(r.contacts[p].pressure, extrapolated.pressure),
                                relative_change(r.contacts[p].velocity, extrapolated.velocity));
      if (r.disagreement <= r.agreement_tolerance()) {
        r.check_converged = true;
        break;
      }
    }
    failure.clear();
    previous = std::move(next);
  }
  r.error = std::isnan(r.disagreement) ? kNaN : std::max(r.change, r.disagreement);
  if (!r.check_converged) {
    r.message = "its check by " + std::string(to_string(kind_of(r.check_method))) +
                (std::isnan(r.disagreement)
                     ? " could not be computed: " + failure
                     : " disagrees by " + format_value(r.disagreement) + " (more than " +
                           format_value(r.agreement_tolerance()) + ") after " +
                           std::to_string(r.check_refinements) + " halvings");
  }
  return r;
}

}  // namespace impactid
