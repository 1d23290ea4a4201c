// simulate_model_batch(): on a user's sparse model every lane gives simulate()'s numbers bit for
// bit (issue 37: lanes on sparse systems, bit-identical to the point-by-point run), whatever the
// other lanes do; the kernel really takes the lanes it should; and which runs may share a batch.
// Run again at every kernel level (tests/CMakeLists.txt: kernel_levels.*).
#include "core/batch/batched_model.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <string>
#include <variant>
#include <vector>

#include "core/common/kernel_level.hpp"
#include "core/model/model_scene.hpp"
#include "grid_model.hpp"
#include "same_run.hpp"
#include "study/plan/plan.hpp"
#include "study/plan/simulation_settings.hpp"

namespace impactid {
namespace {

using testing::expect_same_run;

// A square grid of Q1 membrane elements, one DOF per node, lumped mass, every node moving toward
// a wall at v = −1 along `contacts` nodes of its first row: a 2D model whose M and Delassus matrix
// are diagonal (each contact its own node), as the kernel needs.
std::shared_ptr<const Model> grid_model(int side, int contacts) {
  const std::shared_ptr<Model> model = testing::grid_membrane(side);
  for (int c = 0; c < contacts; ++c) {
    const Eigen::Index dof = static_cast<Eigen::Index>(c) * (side - 1) / (contacts - 1);
    model->contacts.push_back({"c" + std::to_string(c), -1, dof, 3.0 + 0.5 * c, 2.0, dof});
  }
  return model;
}

struct Lane {
  std::string name;
  AssembledScene scene;
  MethodParams method = CentralDifferenceParams{};
};

// What a batch did: the lanes the kernel stepped, and the runs that ended unstable.
struct BatchOutcome {
  int stepped = 0;
  int unstable = 0;
};

// Runs `lanes` as one batch and each alone through simulate(), and compares everything.
BatchOutcome expect_batch_equals_scalar(const std::vector<Lane>& lanes, const RunOptions& options = {}) {
  std::vector<const AssembledScene*> scenes;
  std::vector<MethodParams> methods;
  for (const Lane& lane : lanes) {
    EXPECT_TRUE(model_batchable(lane.scene, lane.method, options)) << lane.name;
    EXPECT_TRUE(same_model_batch(lanes[0].scene, options, lane.scene, options)) << lane.name;
    scenes.push_back(&lane.scene);
    methods.push_back(lane.method);
  }
  ModelBatchWorkspace batch;
  std::vector<RunSummary> summaries(lanes.size());
  simulate_model_batch(scenes, methods, options, batch, summaries);
  SimulationWorkspace scalar;
  BatchOutcome out{.stepped = batch.kernel_lanes()};
  for (std::size_t k = 0; k < lanes.size(); ++k) {
    const RunSummary want = simulate(lanes[k].scene, lanes[k].method, options, scalar);
    expect_same_run(summaries[k], batch.traces[k], want, scalar.trace,
                    lanes[k].name + " (kernels " + to_string(kernel_level()) + ")");
    // A run that finished met its contact: the comparison covers the forces, not only flight.
    double peak = 0.0;
    for (const double p : scalar.trace.pressure) peak = std::isfinite(p) ? std::max(peak, p) : peak;
    if (want.status == RunStatus::ok) {
      EXPECT_GT(peak, 0.0) << lanes[k].name;
    }
    out.unstable += want.status == RunStatus::unstable ? 1 : 0;
  }
  return out;
}

// The scene at a Courant number (Δt·ω/2) and end time.
AssembledScene at(const std::shared_ptr<const Model>& model, double courant, double t_end,
                  const char* primary = nullptr) {
  ModelScene scene{model, 2.0 * courant / model->omega_bound, t_end};
  if (primary) scene.primary_contact = primary;
  return assemble(scene);
}

bool kernels_here() { return kernel_level() != KernelLevel::baseline; }

// A Courant sweep (each lane its own Δt, hence its own free flight, sample count and left-hand
// matrix), lanes that end at different times, lanes above the explicit limit (which the kernel
// hands to simulate(): their energy is the plain one) and, on x86-64-v3, two sub-batches of 8.
TEST(BatchedModel, ACourantSweepEqualsSimulateLaneByLane) {
  const auto model = grid_model(12, 5);
  std::vector<Lane> lanes;
  for (int k = 0; k < kBatchLanes; ++k) {
    const double courant = 0.3 + 0.05 * k;  // the last ones above the limit of 1
    const double t_end = k % 3 == 0 ? 14.0 : 21.0;
    lanes.push_back({"courant " + std::to_string(courant), at(model, courant, t_end)});
  }
  const BatchOutcome outcome = expect_batch_equals_scalar(lanes);
  const int stepped = outcome.stepped;
  if (kernels_here()) {
    EXPECT_GE(stepped, 10);          // the kernel took the stable lanes
    EXPECT_LT(stepped, kBatchLanes);  // and left the others to simulate()
  } else {
    EXPECT_EQ(stepped, 0);
  }
}

// The energy checked at every sample (every sample an event), each lane with its own primary
// contact and end time, and an energy bound at the edge of what the method's own energy does
// (central difference conserves it up to the contacts, which take energy away: the bound is met
// at every check, so every lane runs to its end through the check path).
TEST(BatchedModel, EventsAtEverySampleAndOwnPrimaries) {
  const auto model = grid_model(9, 3);
  RunOptions options;
  options.energy_check_interval = 1;
  std::vector<Lane> lanes;
  lanes.push_back({"c0 primary", at(model, 0.5, 12.0)});
  lanes.push_back({"c2 primary", at(model, 0.7, 12.0, "c2")});
  lanes.push_back({"c1 primary", at(model, 0.9, 9.0, "c1")});
  EXPECT_EQ(expect_batch_equals_scalar(lanes, options).unstable, 0);

  RunOptions tight;
  tight.energy_growth_limit = 1.0 + 1e-15;
  tight.energy_check_interval = 3;
  const BatchOutcome outcome = expect_batch_equals_scalar(lanes, tight);
  if (kernels_here()) {
    EXPECT_EQ(outcome.stepped, 3);
  }
}

// A stiffness whose two triangles differ in one bit (as an assembly's round-off may leave them)
// and a mass with a stored zero off its diagonal: the kernel then scatters M and K column by
// column, as the scalar product does, instead of its one-pass predictor (which needs K exactly
// symmetric and M stored as its diagonal).
TEST(BatchedModel, AStiffnessNotExactlySymmetric) {
  auto model = std::make_shared<Model>(*grid_model(8, 3));
  model->stiffness.coeffRef(9, 10) = std::nextafter(model->stiffness.coeff(9, 10), 0.0);
  model->mass.coeffRef(1, 0) = 0.0;
  model->mass.makeCompressed();
  std::vector<Lane> lanes;
  for (const double courant : {0.4, 0.6, 0.8}) {
    lanes.push_back({"courant " + std::to_string(courant), at(model, courant, 12.0)});
  }
  const BatchOutcome outcome = expect_batch_equals_scalar(lanes);
  if (kernels_here()) {
    EXPECT_EQ(outcome.stepped, 3);
  }
}

// The shipped block (examples/block: plane strain, 1722 DOFs, its own contacts), swept over its
// Courant number as a plan would.
TEST(BatchedModel, TheShippedBlock) {
  const std::filesystem::path file =
      std::filesystem::path(IMPACTID_SOURCE_DIR) / "examples/block/scene.toml";
  const ModelScene base = *std::get<Simulation>(build(load_scene_file(file))).model();
  std::vector<Lane> lanes;
  for (const double factor : {0.5, 0.6, 0.75, 0.9}) {
    ModelScene scene = base;
    scene.dt = base.dt * factor;
    lanes.push_back({"dt x " + std::to_string(factor), assemble(scene)});
  }
  const BatchOutcome outcome = expect_batch_equals_scalar(lanes);
  EXPECT_EQ(outcome.unstable, 0);
  if (kernels_here()) {
    EXPECT_EQ(outcome.stepped, 4);
  }
}

TEST(BatchedModel, WhatBatches) {
  const auto model = grid_model(6, 2);
  const AssembledScene scene = at(model, 0.5, 8.0);
  RunOptions options;
  EXPECT_TRUE(model_batchable(scene, CentralDifferenceParams{}, options));
  EXPECT_FALSE(model_batchable(scene, HhtParams{}, options));
  EXPECT_FALSE(model_batchable(
      scene, CentralDifferenceParams{.velocity = CdmVelocity::backward}, options));
  RunOptions history = options;
  history.record_history = true;
  EXPECT_FALSE(model_batchable(scene, CentralDifferenceParams{}, history));
  RunOptions penalty = options;
  penalty.contact.law = ContactLaw::penalty;
  EXPECT_FALSE(model_batchable(scene, CentralDifferenceParams{}, penalty));
  ModelScene damped{model, scene.dt, 8.0};
  damped.rayleigh_mass = 0.1;
  EXPECT_FALSE(model_batchable(assemble(damped), CentralDifferenceParams{}, options));
  // The built-in rod is no sparse model.
  EXPECT_FALSE(model_batchable(assemble(RodScene{}), CentralDifferenceParams{}, options));

  // Another Δt shares a batch; other matrices or options do not.
  EXPECT_TRUE(same_model_batch(scene, options, at(model, 0.8, 5.0), options));
  EXPECT_FALSE(same_model_batch(scene, options, at(grid_model(6, 3), 0.5, 8.0), options));
  auto stiffer = std::make_shared<Model>(*model);
  stiffer->stiffness *= 2.0;
  EXPECT_FALSE(same_model_batch(scene, options, at(stiffer, 0.5, 8.0), options));
  RunOptions other = options;
  other.energy_check_interval = 4;
  EXPECT_FALSE(same_model_batch(scene, options, scene, other));
}

}  // namespace
}  // namespace impactid
