// What a run of a user's model (core/model_scene.hpp) is measured against, sampled at its samples
// t_i = i·Δt (i = 1..N):
// - the history the user supplies (ReferenceHistory: a CSV file of the scene), linearly
//   interpolated in t between its samples, its own values where a sample time matches to 1e-9·Δt
//   (a history written at the run's samples, as `impactid export-model` writes the exact solution
//   of a built-in scene, is taken as it is); or
// - a converged solution: the scene run by a reference method (default HHT α = −0.3, δ = −α:
//   second order, and damped) at Δt/2^k, k = 1, 2, …, until the primary contact's pressure and
//   velocity change by less than a tolerance between two halvings, in the form of eq. 18
//   (Σ|x_k − x_{k−1}| / Σ|x_k| over the samples). A refined run's sample t_i is its step i·2^k:
//   no interpolation enters.
// Unlike a scene of bodies (core/scene_reference.hpp), a model's mesh is the user's and cannot be
// refined: the converged solution is that of the semi-discrete model, not of the continuum.
//
// Thread safety: values; model_reference() is reentrant.
#pragma once

#include <string>
#include <vector>

#include "core/model_scene.hpp"
#include "core/scene_reference.hpp"

namespace impactid {

struct ModelReference {
  ModelScene scene;                      ///< what it is the reference of (a cache key)
  ReferenceOptions options;              ///< and with which options
  std::vector<ContactSamples> contacts;  ///< Model::contacts order; empty vectors: none
  /// −1: the supplied history; k >= 1: the converged solution at Δt/2^k.
  int refinements = -1;
  double dt = 0.0;  ///< the reference's step (the supplied history's: NaN)
  /// The relative change at the last halving (NaN for a supplied history).
  double change = std::numeric_limits<double>::quiet_NaN();
  bool converged = true;  ///< false when max_refinements ran out or a refined run failed
  std::string message;    ///< why not converged, or why not usable

  /// Whether the primary contact has samples to compare with.
  bool usable(int primary) const;
  /// "supplied: FILE" or "converged: hht at dt/2^k = … s, relative change …".
  std::string description() const;
};

/// Options of a model's converged reference: HHT α = −0.3, tolerance 1e-3, at most 10 halvings
/// (1024 times the run's steps; each halving doubles the cost).
ReferenceOptions model_reference_defaults();

/// The reference of a valid model scene. Never throws: a reference that cannot be had is not
/// usable(), with the reason in `message`.
ModelReference model_reference(const ModelScene& scene, const ReferenceOptions& options);

}  // namespace impactid
