// The references of scenes of bodies and of users' models, their refined runs made by simulate()
// (core/reference/ computes them; this is where they meet the run).
//
// Thread safety: reentrant, as simulate().
#pragma once

#include "core/reference/model_reference.hpp"
#include "core/reference/scene_reference.hpp"

namespace impactid {

/// scene_reference(scene, options, run) with simulate() as the run.
SceneReference scene_reference(const Scene& scene, const ReferenceOptions& options);

/// model_reference(scene, options, run) with simulate() as the run.
ModelReference model_reference(const ModelScene& scene, const ReferenceOptions& options);

/// simulate() with the default run options, as the references run their refined scenes.
ReferenceRun simulate_for_reference();

}  // namespace impactid
