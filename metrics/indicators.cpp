#include "metrics/indicators.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <vector>

#include "core/reference/exact_solution.hpp"
#include "metrics/peak_count.hpp"
#include "metrics/relative_error.hpp"

namespace impactid {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// What one pass over a run's samples gathers with the exact solution beside them: eq. 18's sums,
// p_max, the contact episodes and the peaks. (Three passes, the sums and one per peak count, cost a
// visible share of a sweep point's run: docs/performance.md.)
struct SamplePass {
  SamplePass(double pressure_prominence, double velocity_prominence)
      : pressure_peaks(pressure_prominence), velocity_peaks(velocity_prominence) {}

  RelativeErrorSum pressure_error, velocity_error;
  double p_max = -std::numeric_limits<double>::infinity();
  long episodes = 0;
  bool in_contact = false;
  PeakCounter pressure_peaks, velocity_peaks;

  // One sample, in the order of the samples: each sum is the same sequence of adds as the
  // separate loops this pass replaced, so the same bits.
  [[gnu::always_inline]] void add(double exact_pressure, double exact_velocity, double pressure,
                                  double velocity) {
    pressure_error.add(exact_pressure, pressure);
    velocity_error.add(exact_velocity, velocity);
    p_max = std::max(p_max, pressure);
    const bool active = pressure > 0.0;
    if (active && !in_contact) ++episodes;
    in_contact = active;
    pressure_peaks.add(pressure);
    velocity_peaks.add(velocity);
  }
};

// The pass of a run of `scene` whose options are `options`.
SamplePass start_pass(const RodScene& scene, const RodSceneDerived& derived,
                      const IndicatorOptions& options) {
  return {options.peak_prominence * derived.pressure_scale,
          options.peak_prominence * std::abs(scene.velocity)};
}

// The indicators from a finished pass: the peak counts, ratios and the far wall's indicators.
Indicators finish(const RodScene& scene, const RodSceneDerived& derived, const ContactTrace& trace,
                  const RunSummary& summary, const SamplePass& pass) {
  constexpr double nan = kNaN;
  Indicators out;
  out.eps_p = pass.pressure_error.value();
  out.eps_v = pass.velocity_error.value();
  out.nop_p = static_cast<double>(pass.pressure_peaks.peaks());
  out.nop_v = static_cast<double>(pass.velocity_peaks.peaks());
  out.p_max = pass.p_max;
  out.p_max_ratio = derived.pressure_scale > 0.0 ? pass.p_max / derived.pressure_scale : nan;
  out.contact_episodes = static_cast<double>(pass.episodes);
  out.energy_ratio =
      summary.initial_energy > 0.0 ? summary.final_energy / summary.initial_energy : nan;
  out.far_contact_episodes = nan;
  out.impacts = nan;
  // Tracked with a far wall, or with a contact law that lets the node penetrate.
  out.max_penetration = summary.max_penetration;
  if (scene.far_gap) {
    // The wall that alone held the rod last. A sample where both walls push is a hand-over (or a
    // rod pressed between them): it does not change `last`, so it never counts an impact, except
    // when it is the first contact of the run (`both`: one impact, continued by either wall).
    enum class Wall { none, main, far, both } last = Wall::none;
    long far_episodes = 0, impacts = 0;
    bool far_in_contact = false;
    for (long i = 0; i < trace.size(); ++i) {
      const bool main_active = trace.pressure[i] > 0.0;
      const bool far_active = trace.far_pressure[i] > 0.0;
      if (far_active && !far_in_contact) ++far_episodes;
      far_in_contact = far_active;
      if (main_active && far_active) {
        if (last == Wall::none) {
          ++impacts;
          last = Wall::both;
        }
      } else if (main_active || far_active) {
        const Wall wall = main_active ? Wall::main : Wall::far;
        if (last != wall && last != Wall::both) ++impacts;
        last = wall;
      }
    }
    out.far_contact_episodes = static_cast<double>(far_episodes);
    out.impacts = static_cast<double>(impacts);
  }
  return out;
}

Indicators not_results() {
  return {kNaN, kNaN, kNaN, kNaN, kNaN, kNaN, kNaN, kNaN, kNaN, kNaN, kNaN};
}

}  // namespace

void evaluate_indicators(const RodScene& scene, std::span<const ContactTrace* const> traces,
                         std::span<const RunSummary> summaries,
                         std::span<const IndicatorOptions> options, std::span<Indicators> out) {
  assert(summaries.size() == traces.size() && options.size() == traces.size() &&
         out.size() == traces.size());
  // The exact solution at the samples, once for all the runs. (Evaluated per sample beside 16
  // runs' passes instead, the passes' sums lived in memory and took longer per run than one
  // run's pass with the exact solution evaluated in its loop.)
  const RodImpactExact exact(scene);
  const RodSceneDerived derived = derive(scene);
  std::vector<double> exact_pressure, exact_velocity;
  for (std::size_t k = 0; k < traces.size(); ++k) {
    if (summaries[k].status != RunStatus::ok) {
      out[k] = not_results();
      continue;
    }
    const long size = traces[k]->size();
    // One scene, one step count: every trace has the same samples.
    assert(exact_pressure.empty() || static_cast<long>(exact_pressure.size()) == size);
    if (exact_pressure.empty()) {
      exact_pressure.resize(static_cast<std::size_t>(size));
      exact_velocity.resize(static_cast<std::size_t>(size));
      for (long i = 0; i < size; ++i) {
        const ContactNodeValues e = exact.at_sample(i + 1);
        exact_pressure[static_cast<std::size_t>(i)] = e.pressure;
        exact_velocity[static_cast<std::size_t>(i)] = e.velocity;
      }
    }
    SamplePass pass = start_pass(scene, derived, options[k]);  // a local, in registers
    const double* pressure = traces[k]->pressure.data();
    const double* velocity = traces[k]->velocity.data();
    for (long i = 0; i < size; ++i) {
      const auto j = static_cast<std::size_t>(i);
      pass.add(exact_pressure[j], exact_velocity[j], pressure[i], velocity[i]);
    }
    out[k] = finish(scene, derived, *traces[k], summaries[k], pass);
  }
}

Indicators evaluate_indicators(const RodScene& scene, const ContactTrace& trace,
                               const RunSummary& summary, const IndicatorOptions& options) {
  Indicators out;
  const ContactTrace* const traces[] = {&trace};
  evaluate_indicators(scene, traces, std::span(&summary, 1), std::span(&options, 1),
                      std::span(&out, 1));
  return out;
}

namespace {

// Each contact's indicators against its reference samples, with its pressure and velocity
// scales; the primary contact's as Indicators. Shared by scenes of bodies and models.
Indicators contact_indicators(const std::vector<ContactSamples>& reference,
                              std::span<const double> pressure_scales,
                              std::span<const double> velocity_scales, std::size_t primary_contact,
                              const ContactTrace& trace, const RunSummary& summary,
                              const IndicatorOptions& options,
                              std::span<ContactIndicators> contacts) {
  Indicators primary = not_results();
  for (std::size_t k = 0; k < contacts.size(); ++k) {
    if (summary.status != RunStatus::ok || reference[k].pressure.empty()) {
      contacts[k] = {kNaN, kNaN, kNaN, kNaN, kNaN, kNaN, kNaN};
      continue;
    }
    const ContactSamples& expected = reference[k];
    const double pressure_scale = pressure_scales[k];
    SamplePass pass(options.peak_prominence * pressure_scale,
                    options.peak_prominence * velocity_scales[k]);
    const std::vector<double>& pressure = trace.contact_pressure[k];
    const std::vector<double>& velocity = trace.contact_velocity[k];
    assert(expected.pressure.size() == pressure.size());
    for (std::size_t i = 0; i < pressure.size(); ++i) {
      pass.add(expected.pressure[i], expected.velocity[i], pressure[i], velocity[i]);
    }
    contacts[k] = {pass.pressure_error.value(),
                   pass.velocity_error.value(),
                   static_cast<double>(pass.pressure_peaks.peaks()),
                   static_cast<double>(pass.velocity_peaks.peaks()),
                   pass.p_max,
                   pressure_scale > 0.0 ? pass.p_max / pressure_scale : kNaN,
                   static_cast<double>(pass.episodes)};
  }
  if (summary.status != RunStatus::ok) return primary;
  const ContactIndicators& p = contacts[primary_contact];
  primary.eps_p = p.eps_p;
  primary.eps_v = p.eps_v;
  primary.nop_p = p.nop_p;
  primary.nop_v = p.nop_v;
  primary.p_max = p.p_max;
  primary.p_max_ratio = p.p_max_ratio;
  primary.contact_episodes = p.contact_episodes;
  primary.energy_ratio =
      summary.initial_energy > 0.0 ? summary.final_energy / summary.initial_energy : kNaN;
  primary.max_penetration = summary.max_penetration;
  return primary;
}

double largest_magnitude(const std::vector<double>& x) {
  double m = 0.0;
  for (const double v : x) m = std::max(m, std::abs(v));
  return m;
}

}  // namespace

double contact_pressure_scale(const Scene& scene, const SceneContact& c, double velocity_scale) {
  const Body& body = scene.bodies[static_cast<std::size_t>(c.left_body >= 0 ? c.left_body : 0)];
  const Segment& seg = c.left_body >= 0 ? body.segments.back() : body.segments.front();
  return seg.density * std::sqrt(seg.youngs_modulus / seg.density) * velocity_scale;
}

Indicators evaluate_indicators(const Scene& scene, const SceneReference& reference,
                               const ContactTrace& trace, const RunSummary& summary,
                               const IndicatorOptions& options,
                               std::span<ContactIndicators> contacts) {
  const std::vector<SceneContact> list = scene_contacts(scene);
  const SceneDerived derived = derive(scene);
  assert(contacts.size() == list.size() && trace.contact_pressure.size() == list.size());
  std::vector<double> pressure_scales(list.size()), velocity_scales(list.size());
  for (std::size_t k = 0; k < list.size(); ++k) {
    pressure_scales[k] = contact_pressure_scale(scene, list[k], derived.velocity_scale);
    velocity_scales[k] = derived.velocity_scale;
  }
  return contact_indicators(reference.contacts, pressure_scales, velocity_scales,
                            static_cast<std::size_t>(derived.primary_contact), trace, summary,
                            options, contacts);
}

Indicators evaluate_indicators(const std::vector<ContactSamples>& reference, int primary,
                               const ContactTrace& trace, const RunSummary& summary,
                               const IndicatorOptions& options,
                               std::span<ContactIndicators> contacts) {
  assert(contacts.size() == reference.size() && trace.contact_pressure.size() == reference.size());
  std::vector<double> pressure_scales(reference.size()), velocity_scales(reference.size());
  for (std::size_t k = 0; k < reference.size(); ++k) {
    pressure_scales[k] = largest_magnitude(reference[k].pressure);
    velocity_scales[k] = largest_magnitude(reference[k].velocity);
  }
  return contact_indicators(reference, pressure_scales, velocity_scales,
                            static_cast<std::size_t>(primary), trace, summary, options, contacts);
}

}  // namespace impactid
