// One run of a scene of bodies with one contact (the clamped bar, the bouncing bar), measured
// against the scene's reference: its summary, trace, indicators and the reference itself, for
// tests/clamped_bar_scene_test.cpp and tests/bouncing_bar_scene_test.cpp. Header-only.
#pragma once

#include <vector>

#include "core/model/scene.hpp"
#include "core/model/scene_assembly.hpp"
#include "core/run/references.hpp"
#include "core/run/simulation.hpp"
#include "metrics/indicators.hpp"

namespace impactid::testing {

struct BarRun {
  RunSummary summary;
  ContactTrace trace;
  Indicators indicators;
  SceneReference reference;
};

inline BarRun run_bar(const Scene& scene, const MethodParams& method, bool history = false,
                      const ContactTreatment& contact = {}) {
  SimulationWorkspace ws;
  BarRun out;
  out.summary = simulate(assemble(scene), method,
                         RunOptions{.record_history = history, .contact = contact}, ws);
  out.trace = ws.trace;
  out.reference = scene_reference(scene, ReferenceOptions{});
  std::vector<ContactIndicators> contacts(1);
  out.indicators = evaluate_indicators(scene, out.reference, out.trace, out.summary,
                                       IndicatorOptions{}, contacts);
  return out;
}

}  // namespace impactid::testing
