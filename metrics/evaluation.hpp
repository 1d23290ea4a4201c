// What one simulation measured: its run summary (status, energy, contact counters), the paper's
// indicators at the contact node, and, for a scene of bodies or a user's model, every contact's
// indicators and the reference they were measured against. The record a sweep point stores and
// `impactid simulate` prints; study/studies/evaluation.hpp computes it.
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "core/run_record.hpp"
#include "metrics/indicators.hpp"

namespace impactid {

struct Evaluation {
  RunSummary summary;
  Indicators indicators;  ///< with a scene of bodies: its primary contact's
  /// A scene of bodies: every contact's indicators, in scene_contacts() order; empty for the rod.
  std::vector<ContactIndicators> contacts;
  /// A scene of bodies: its reference (core/scene_reference.hpp), 0 for the exact solution or
  /// k for a converged one at h/2^k and Δt/2^k, and the relative change at its last halving (NaN
  /// for the exact one). A model (core/model_reference.hpp): −1 for a supplied history, k for a
  /// converged solution at Δt/2^k. NaN for the rod.
  double reference_refinements = std::numeric_limits<double>::quiet_NaN();
  double reference_change = std::numeric_limits<double>::quiet_NaN();
  /// A model: its reference's step (NaN for a supplied history or another scene), and the
  /// reference described in words (empty for the rod).
  double reference_dt = std::numeric_limits<double>::quiet_NaN();
  std::string reference;
};

}  // namespace impactid
