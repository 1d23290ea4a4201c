// The explicit schemes with stages or model-based matrices on a user's sparse model (Noh–Bathe and
// Kim's scheme, core/methods/noh_bathe.hpp and core/methods/kim_explicit.hpp with
// core/contact/sparse_explicit_stage_contact.hpp; KR-α, core/methods/sparse_kr_alpha.hpp):
// - the paper's rod as a model of its own tridiagonal matrices (examples/rod), run once by the
//   tridiagonal path and once as a sparse model, gives the same run to round-off, for each method
//   and each contact law it takes, with a lumped and a consistent mass, with and without damping;
// - the shipped block (examples/block, 41 coupled contacts), lumped and consistent: the Signorini
//   conditions at every sample and stage, and through simulate() λ >= 0 and the gaps at every
//   reported sample, the energy bounded;
// - the stable step, its warning and the refusals read as on the tridiagonal path.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "core/contact/stable_step.hpp"
#include "core/methods/kim_explicit.hpp"
#include "core/methods/noh_bathe.hpp"
#include "core/methods/sparse_kr_alpha.hpp"
#include "core/model/model_scene.hpp"
#include "core/model/scene_assembly.hpp"
#include "core/run/simulation.hpp"
#include "signorini_check.hpp"
#include "study/formats/matrix_market.hpp"
#include "study/plan/plan.hpp"
#include "study/plan/simulation_settings.hpp"
#include "test_support.hpp"

namespace impactid {
namespace {

const std::filesystem::path kExamples = std::filesystem::path(IMPACTID_SOURCE_DIR) / "examples";

// A scene of the examples, as `impactid` builds it from its scene file.
ModelScene example_model(const std::string& name) {
  return *std::get<Simulation>(build(load_scene_file(kExamples / name / "scene.toml"))).model();
}

// The same assembled scene with its matrices and its wall as a sparse model: the sparse path
// runs it (model_scene.cpp would pick the tridiagonal one for these matrices).
AssembledScene as_sparse_model(const AssembledScene& tridiagonal) {
  AssembledScene out = tridiagonal;
  const SecondOrderSystem& system = tridiagonal.system;
  auto sparse = std::make_shared<SparseSystem>();
  sparse->mass = to_sparse(system.mass);
  sparse->stiffness = to_sparse(system.stiffness);
  sparse->damping = to_sparse(system.damping);
  sparse->constraints = {{system.contact_dof, -1, system.gap}};
  out.sparse = std::move(sparse);
  out.contact_columns = true;  // a model's runs record every contact (the built-in rod's need not)
  return out;
}

// One simulate() run of an assembled scene with its trace copied out of the workspace.
testing::Run run(const AssembledScene& scene, const MethodParams& method,
                 const RunOptions& options = testing::stepping_options()) {
  SimulationWorkspace workspace;
  testing::Run r;
  r.summary = simulate(scene, method, options, workspace);
  r.trace = workspace.trace;
  return r;
}

struct MethodCase {
  std::string name;
  MethodParams method;
};

// Every explicit scheme with stages or model-based matrices; each takes every contact law.
std::vector<MethodCase> explicit_methods() {
  return {{"noh-bathe", NohBatheParams{}},
          {"noh-bathe p=0.75", NohBatheParams{.p = 0.75}},
          {"kim-explicit", KimExplicitParams{}},
          {"kim-explicit p=1/3", KimExplicitParams{.p = 1.0 / 3.0}},
          {"kim-explicit p=1/2", KimExplicitParams{.p = 0.5}},
          {"kr-alpha", KrAlphaParams{}},
          {"kr-alpha rho_inf=0", KrAlphaParams{.rho_inf = 0.0}}};
}

constexpr std::array<ContactLaw, 3> kLaws = {ContactLaw::lagrange, ContactLaw::penalty,
                                             ContactLaw::augmented_lagrangian};

// The laws as a run uses them: the augmented Lagrangian with a spring stiff enough to converge
// well within its cap on the rod.
RunOptions options_for(ContactLaw law) {
  RunOptions options = testing::stepping_options();
  options.contact = {.law = law,
                     .penalty_factor = law == ContactLaw::augmented_lagrangian ? 100.0 : 1.0,
                     .augmented_tolerance = 1e-10,
                     .augmented_max_iterations = 1000};
  return options;
}

double largest_abs(const std::vector<double>& x) {
  double out = 0.0;
  for (const double v : x) out = std::max(out, std::abs(v));
  return out;
}

// Runs the scene by the tridiagonal path and as a sparse model and compares every sample's
// pressure and velocity, the summaries' status, stable step and warning.
void expect_same_run(const AssembledScene& tridiagonal, const MethodCase& m, ContactLaw law,
                     double tolerance) {
  SCOPED_TRACE(m.name + " " + to_string(law));
  const AssembledScene sparse = as_sparse_model(tridiagonal);
  const RunOptions options = options_for(law);
  const testing::Run a = run(tridiagonal, m.method, options);
  const testing::Run b = run(sparse, m.method, options);
  ASSERT_EQ(a.summary.status, RunStatus::ok) << a.summary.message;
  ASSERT_EQ(b.summary.status, RunStatus::ok) << b.summary.message;
  EXPECT_EQ(a.summary.steps, b.summary.steps);
  EXPECT_EQ(a.summary.warning, b.summary.warning);
  if (std::isnan(a.summary.stable_dt)) {  // KR-α: unconditionally stable, none reported
    EXPECT_TRUE(std::isnan(b.summary.stable_dt));
  } else {
    EXPECT_NEAR(a.summary.stable_dt, b.summary.stable_dt, 1e-15 * a.summary.stable_dt);
  }
  EXPECT_EQ(a.summary.contact_iterations > 0, b.summary.contact_iterations > 0);
  const double pressure_scale = largest_abs(a.trace.pressure);
  const double velocity_scale = largest_abs(a.trace.velocity);
  ASSERT_GT(pressure_scale, 0.0);
  EXPECT_LT(testing::max_abs_difference(a.trace.pressure, b.trace.pressure),
            tolerance * pressure_scale);
  EXPECT_LT(testing::max_abs_difference(a.trace.velocity, b.trace.velocity),
            tolerance * velocity_scale);
  EXPECT_LT(testing::max_abs_difference(a.trace.displacement, b.trace.displacement),
            tolerance * largest_abs(a.trace.displacement));
  EXPECT_NEAR(a.summary.final_energy, b.summary.final_energy, tolerance * a.summary.initial_energy);
}

TEST(SparseExplicit, TheRodsModelFileRunsAsOnTheTridiagonalPath) {
  const AssembledScene rod = assemble(example_model("rod"));
  ASSERT_FALSE(rod.sparse);  // the tridiagonal path, with the paper's named wall
  ASSERT_GE(rod.system.contact_dof, 0);
  for (const MethodCase& m : explicit_methods()) {
    for (const ContactLaw law : kLaws) expect_same_run(rod, m, law, 1e-9);
  }
}

// A consistent mass (factored, not inverted entry by entry) and stiffness damping (KR-α's D and E
// with C, the stages' C·ṽ).
TEST(SparseExplicit, AConsistentDampedRodRunsAsOnTheTridiagonalPath) {
  RodScene rod;
  rod.mass = MassMatrix::consistent;
  rod.rayleigh_stiffness = 1e-8;
  rod.t_end = 4e-4;
  const AssembledScene scene = assemble(rod);
  for (const MethodCase& m : explicit_methods()) {
    for (const ContactLaw law : kLaws) expect_same_run(scene, m, law, 1e-9);
  }
}

// Above the stable step the sparse run is flagged by the same words and numbers before it starts,
// with and without the penalty's springs (then the step is within the spring-free limit).
TEST(SparseExplicit, AStepAboveTheStableStepIsFlaggedAsOnTheTridiagonalPath) {
  AssembledScene rod = assemble(example_model("rod"));
  const double bound = highest_frequency_squared_bound(rod.system);
  for (const auto& [name, method, omega] :
       std::vector<std::tuple<std::string, MethodParams, double>>{
           {"noh-bathe", NohBatheParams{}, noh_bathe_critical_omega(0.54)},
           {"kim-explicit", KimExplicitParams{.p = 0.4}, kim_explicit_critical_omega(0.4)}}) {
    for (const ContactLaw law : {ContactLaw::lagrange, ContactLaw::penalty}) {
      SCOPED_TRACE(name + " " + to_string(law));
      AssembledScene scene = rod;
      // Lagrange: 1.01 times the stable step; penalty (springs of K's diagonal at the wall): the
      // spring-free stable step, above the one with the springs.
      scene.dt = (law == ContactLaw::lagrange ? 1.01 : 1.0) * omega / std::sqrt(bound);
      scene.step_count = 50;
      RunOptions options = options_for(law);
      options.energy_growth_limit = 1e300;  // the warning is the subject, not the growth
      const testing::Run a = run(scene, method, options);
      const testing::Run b = run(as_sparse_model(scene), method, options);
      EXPECT_NE(a.summary.warning.find("exceeds " + name + "'s stable step"), std::string::npos)
          << a.summary.warning;
      EXPECT_EQ(a.summary.warning, b.summary.warning);
      EXPECT_GT(b.summary.stable_dt, 0.0);
      EXPECT_NEAR(a.summary.stable_dt, b.summary.stable_dt, 1e-15 * a.summary.stable_dt);
      EXPECT_LT(b.summary.stable_dt, scene.dt);
    }
  }
}

// A mass that is not positive definite is named by its DOF.
TEST(SparseExplicit, RefusalsNameWhatIsWrong) {
  AssembledScene rod = as_sparse_model(assemble(example_model("rod")));
  auto bad_mass = std::make_shared<SparseSystem>(*rod.sparse);
  bad_mass->mass.coeffRef(7, 7) = -1.0;
  AssembledScene bad = rod;
  bad.sparse = bad_mass;
  for (const auto& [name, method] :
       std::vector<std::pair<std::string, MethodParams>>{{"noh-bathe", NohBatheParams{}},
                                                         {"kim-explicit", KimExplicitParams{}},
                                                         {"kr-alpha", KrAlphaParams{}}}) {
    const testing::Run r = run(bad, method);
    EXPECT_EQ(r.summary.status, RunStatus::failed);
    EXPECT_EQ(r.summary.message,
              name + ": the mass matrix is not positive definite: pivot -1 at DOF 7");
  }
}

// The shipped block (examples/block: 1722 DOFs, 41 contacts on its bottom edge), with its lumped
// mass or its consistent one (M_consistent.mtx).
AssembledScene block(bool consistent) {
  ModelScene scene = example_model("block");
  if (consistent) {
    auto model = std::make_shared<Model>(*scene.model);
    model->mass = read_matrix_market(kExamples / "block" / "M_consistent.mtx");
    scene.model = model;
  }
  AssembledScene out = assemble(scene);
  EXPECT_TRUE(out.sparse);
  return out;
}

// Where a sample's multiplier is complementary (the headers): to the gap at the next point the
// scheme computes (forward increments), Kim's to the sample's own gap where that binds.
enum class Complementary { next_substep, sample_or_next_substep, next_sample };

// The steppers themselves on the block: λ >= 0 and the gaps at every sample, and for the stage
// schemes at every stage (Lagrange: the constraints hold at every point of the time grid,
// core/methods/noh_bathe.hpp and core/methods/kim_explicit.hpp), and each sample's multiplier
// complementary to the gap its header names, checked with the test's own arithmetic. `sample_gap`
// bounds the samples' gaps (below: Kim's scheme with a consistent mass).
template <class Stepper, class Coefficients>
void expect_signorini_on_the_block(const AssembledScene& scene, const Coefficients& coefficients,
                                   Complementary complementary, double sample_gap,
                                   const std::string& what) {
  SCOPED_TRACE(what);
  const SparseSystem& system = *scene.sparse;
  const auto m = static_cast<Eigen::Index>(system.constraints.size());
  State s = testing::initial_state(scene, m);
  Stepper stepper;
  ASSERT_TRUE(stepper.initialize(system, coefficients, scene.dt, s));
  testing::SignoriniRecord samples, substeps;
  const double gap = system.constraints.front().gap;
  State previous = s;
  double worst_complementarity = 0.0;
  long pushing = 0;
  for (long i = 0; i < scene.step_count; ++i) {
    stepper.step(system, s);
    testing::record_signorini(system, s, samples);
    const State* sub = nullptr;
    if constexpr (requires { stepper.substep_state(); }) {
      sub = &stepper.substep_state();
      testing::record_signorini(system, *sub, substeps);
    }
    for (Eigen::Index k = 0; k < m && i > 0; ++k) {
      if (!(previous.multipliers[k] > 0.0)) continue;
      const Constraint& c = system.constraints[static_cast<std::size_t>(k)];
      double g = 0.0;
      switch (complementary) {
        case Complementary::next_substep:
          g = std::abs(testing::violation(c, sub->u));
          break;
        case Complementary::sample_or_next_substep:
          g = std::min(std::abs(testing::violation(c, previous.u)),
                       std::abs(testing::violation(c, sub->u)));
          break;
        case Complementary::next_sample:
          g = std::abs(testing::violation(c, s.u));
          break;
      }
      worst_complementarity = std::max(worst_complementarity, g);
      ++pushing;
    }
    previous = s;
  }
  // Coupled constraints (the consistent mass couples neighbours): Murty's tolerance, not a snap.
  EXPECT_GE(samples.min_multiplier, 0.0);
  EXPECT_LE(samples.max_violation, sample_gap);
  EXPECT_LE(worst_complementarity, std::max(1e-9 * gap, sample_gap));
  EXPECT_GT(pushing, 41);
  if (complementary != Complementary::next_sample) {
    EXPECT_GE(substeps.min_multiplier, 0.0);
    EXPECT_LE(substeps.max_violation, 1e-9 * gap);
    EXPECT_GT(substeps.pushing, 41);
  }
}

TEST(SparseExplicit, SignoriniConditionsHoldAtEverySampleAndStageOfTheBlock) {
  for (const bool consistent : {false, true}) {
    const AssembledScene scene = block(consistent);
    const double gap = scene.sparse->constraints.front().gap;
    const std::string mass = consistent ? " consistent" : " lumped";
    expect_signorini_on_the_block<SparseNohBatheExplicit>(scene, noh_bathe_coefficients({}),
                                                          Complementary::next_substep, 1e-9 * gap,
                                                          "noh-bathe" + mass);
    for (const double p : {1.0 / 3.0, 0.5}) {
      // Kim's second stage puts the next force point on the walls by further multipliers that
      // move the sample by s_u·M⁻¹·Gᵀ·μ (s_u = 0 at p = ½). With a lumped mass each pushes only
      // its own DOF, away from its wall; a consistent M⁻¹ has entries of both signs, so one
      // contact's push can move a neighbouring sample node toward its wall: measured 3.2e-4 of
      // the gap at p = ⅓ (core/methods/kim_explicit.cpp). The next force point still holds exactly.
      const double sample_gap = consistent && p < 0.5 ? 1e-3 * gap : 1e-9 * gap;
      expect_signorini_on_the_block<SparseKimExplicit>(
          scene, kim_explicit_coefficients({.p = p}), Complementary::sample_or_next_substep,
          sample_gap, "kim-explicit p=" + std::to_string(p) + mass);
    }
    expect_signorini_on_the_block<SparseKrAlphaExplicit>(scene, kr_alpha_coefficients({}),
                                                         Complementary::next_sample, 1e-9 * gap,
                                                         "kr-alpha" + mass);
  }
}

// Through simulate(), as a user runs the block: every method and law it takes, λ >= 0 for every
// contact at every sample, the gaps at every sample (Lagrange; the augmented Lagrangian within
// its tolerance; the penalty's springs let the nodes in), the energy bounded at every sample.
TEST(SparseExplicit, TheBlockRunsWithEveryMethodAndLaw) {
  for (const bool consistent : {false, true}) {
    const AssembledScene scene = block(consistent);
    const double gap = scene.sparse->constraints.front().gap;
    for (const MethodCase& m : explicit_methods()) {
      for (const ContactLaw law : kLaws) {
        SCOPED_TRACE(m.name + " " + to_string(law) + (consistent ? " consistent" : " lumped"));
        RunOptions options = testing::stepping_options();
        options.contact.law = law;
        if (law == ContactLaw::augmented_lagrangian) {
          options.contact.penalty_factor = 100.0;
          options.contact.augmented_max_iterations = 1000;
        }
        const testing::Run r = run(scene, m.method, options);
        ASSERT_EQ(r.summary.status, RunStatus::ok) << r.summary.message;
        EXPECT_TRUE(r.summary.warning.empty()) << r.summary.warning;
        EXPECT_EQ(r.summary.steps, scene.step_count);
        ASSERT_EQ(r.trace.contact_pressure.size(), 41u);
        EXPECT_TRUE(testing::every_contact_pushes_and_never_pulls(r.trace));
        if (law == ContactLaw::lagrange) {
          // Kim's scheme with a consistent mass at p < ½: above.
          const auto* kim = std::get_if<KimExplicitParams>(&m.method);
          EXPECT_LE(r.summary.max_penetration,
                    (consistent && kim && kim->p < 0.5 ? 1e-3 : 1e-9) * gap);
        } else if (law == ContactLaw::augmented_lagrangian) {
          EXPECT_LE(r.summary.max_penetration, 1e-3 * gap);
          EXPECT_GT(r.summary.contact_iterations, 0);
          EXPECT_EQ(r.summary.unconverged_contact_steps, 0);
        } else {
          EXPECT_GT(r.summary.max_penetration, 0.0);
        }
        EXPECT_LE(*std::max_element(r.trace.energy.begin(), r.trace.energy.end()),
                  1.1 * r.summary.initial_energy);
        // The stage schemes' stable step: Ω_crit/ω_bound with the lumped mass (the block's dt is
        // Courant 0.5 of central difference's), none certified with the consistent one.
        if (!std::holds_alternative<KrAlphaParams>(m.method)) {
          if (consistent) {
            EXPECT_EQ(r.summary.stable_dt, 0.0);
          } else {
            EXPECT_GT(r.summary.stable_dt, scene.dt);
          }
        }
      }
    }
  }
}

}  // namespace
}  // namespace impactid
