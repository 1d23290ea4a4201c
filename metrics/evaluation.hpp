// What one simulation measured: its run summary (status, energy, contact counters), the paper's
// indicators at the contact node, and, for a scene of bodies or a user's model, every contact's
// indicators and the reference they were measured against. The record a sweep point stores and
// `impactid simulate` prints; study/studies/evaluation.hpp computes it.
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "core/common/run_record.hpp"
#include "metrics/indicators.hpp"
#include "metrics/verdict.hpp"

namespace impactid {

struct Evaluation {
  RunSummary summary;
  Indicators indicators;  ///< with a scene of bodies: its primary contact's
  /// A scene of bodies: every contact's indicators, in scene_contacts() order; empty for the rod.
  std::vector<ContactIndicators> contacts;
  /// A scene of bodies: its reference (core/reference/scene_reference.hpp), 0 for the exact
  /// solution or k for a converged one at h/2^k and Δt/2^k, and the relative change at its last
  /// halving (NaN for the exact one). A model (core/reference/model_reference.hpp): −1 for a
  /// supplied history, k for a converged solution at Δt/2^k. NaN for the rod.
  double reference_refinements = std::numeric_limits<double>::quiet_NaN();
  double reference_change = std::numeric_limits<double>::quiet_NaN();
  /// A model: its reference's step (NaN for a supplied history or another scene), and the
  /// reference described in words (empty for the rod).
  double reference_dt = std::numeric_limits<double>::quiet_NaN();
  std::string reference;
  /// Whether the reference can be trusted: false for a converged reference that did not converge
  /// or (a model) whose two methods disagree (core/reference/model_reference.hpp); true for an
  /// exact one.
  bool reference_trusted = true;
  /// The reference's own estimated error, in eq. 18's form on the primary contact (the largest of
  /// its pressure's and velocity's): a model's converged reference, the larger of its last
  /// halving's change and its two methods' difference; a scene of bodies' converged one, its last
  /// change; 0 for an exact solution; NaN for a supplied history. An ε below it is not resolved.
  double reference_error = 0.0;
  /// metrics/verdict.hpp, from the summary's status, the indicators, reference_trusted and the
  /// simulation's thresholds (study/studies/evaluation.cpp sets it).
  Verdict verdict = Verdict::failed;
};

}  // namespace impactid
