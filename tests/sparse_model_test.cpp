// The sparse path of a user's model (core/sparse_*.hpp, core/model/model_scene.hpp): the
// factorisation and its refusals, a two-DOF model against its closed-form solution, the sparse
// integrators against the tridiagonal ones on the paper's rod, the contact solver on many
// constraints, and the refusal of central difference with a consistent mass.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <random>

#include "core/algebra/contact_lcp.hpp"
#include "core/methods/central_difference.hpp"
#include "core/methods/implicit_integrator.hpp"
#include "core/methods/sparse_integrators.hpp"
#include "core/model/model_scene.hpp"
#include "core/model/second_order_system.hpp"
#include "core/model/sparse_factorization.hpp"
#include "core/run/simulation.hpp"

namespace impactid {
namespace {

constexpr double kPi = 3.14159265358979323846;

SparseMatrix sparse(const Eigen::MatrixXd& dense) {
  SparseMatrix a = dense.sparseView();
  a.makeCompressed();
  return a;
}

// A symmetric positive definite matrix with the sparsity of a 2D grid (5-point stencil).
Eigen::MatrixXd grid_matrix(int side) {
  const int n = side * side;
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < side; ++i) {
    for (int j = 0; j < side; ++j) {
      const int k = i * side + j;
      a(k, k) = 4.5;
      if (i > 0) a(k, k - side) = a(k - side, k) = -1.0;
      if (j > 0) a(k, k - 1) = a(k - 1, k) = -1.0;
    }
  }
  return a;
}

TEST(SparseFactorization, SolvesAsTheDenseFactorisation) {
  const Eigen::MatrixXd a = grid_matrix(7);
  SparseFactorization f;
  ASSERT_TRUE(f.factor(sparse(a)));
  Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(a.rows(), -1.0, 2.0);
  const Eigen::VectorXd want = a.ldlt().solve(b);
  f.solve_in_place(b);
  EXPECT_LT((b - want).norm(), 1e-13 * want.norm());
  EXPECT_GT(f.factor_nonzeros(), a.rows());  // fill-in beyond the diagonal
}

TEST(SparseFactorization, NamesTheDofOfANegativePivot) {
  for (const int bad : {0, 7, 30}) {
    Eigen::MatrixXd a = grid_matrix(6);
    a(bad, bad) = -3.0;
    SparseFactorization f;
    EXPECT_FALSE(f.factor(sparse(a)));
    EXPECT_EQ(f.failed_dof(), bad);
    EXPECT_LT(f.failed_pivot(), 0.0);
  }
  // A diagonal matrix (a lumped mass) with a zero entry.
  Eigen::MatrixXd d = Eigen::MatrixXd::Identity(5, 5);
  d(3, 3) = 0.0;
  SparseFactorization f;
  EXPECT_FALSE(f.factor(sparse(d)));
  EXPECT_EQ(f.failed_dof(), 3);
}

// The 7-point Laplacian of a side³ grid plus the identity, built sparse (a 3D model's pattern).
SparseMatrix cube_matrix(int side) {
  const int n = side * side * side;
  std::vector<Eigen::Triplet<double>> entries;
  const auto at = [side](int i, int j, int k) { return (k * side + j) * side + i; };
  for (int k = 0; k < side; ++k) {
    for (int j = 0; j < side; ++j) {
      for (int i = 0; i < side; ++i) {
        const int row = at(i, j, k);
        entries.emplace_back(row, row, 7.0);
        if (i > 0) entries.emplace_back(row, at(i - 1, j, k), -1.0);
        if (i + 1 < side) entries.emplace_back(row, at(i + 1, j, k), -1.0);
        if (j > 0) entries.emplace_back(row, at(i, j - 1, k), -1.0);
        if (j + 1 < side) entries.emplace_back(row, at(i, j + 1, k), -1.0);
        if (k > 0) entries.emplace_back(row, at(i, j, k - 1), -1.0);
        if (k + 1 < side) entries.emplace_back(row, at(i, j, k + 1), -1.0);
      }
    }
  }
  SparseMatrix a(n, n);
  a.setFromTriplets(entries.begin(), entries.end());
  return a;
}

// The ordering is chosen by the factor's size: nested dissection (METIS) on a large 3D pattern,
// where it stores far fewer entries; AMD below kMetisMinimumSize (the shipped 2D block among
// them); none for a diagonal matrix. The solves agree either way.
TEST(SparseFactorization, ChoosesNestedDissectionForALarge3dPatternAndAmdOtherwise) {
  const SparseMatrix cube = cube_matrix(24);  // 13,824 unknowns
  ASSERT_GE(cube.rows(), kMetisMinimumSize);
  SparseFactorization f;
  ASSERT_TRUE(f.factor(cube));
  EXPECT_EQ(f.ordering(), SparseOrdering::metis);
  Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(cube.rows(), -1.0, 2.0);
  const Eigen::VectorXd rhs = b;
  f.solve_in_place(b);
  EXPECT_LT((cube * b - rhs).norm(), 1e-12 * rhs.norm());
  // AMD's factor of the same matrix, for the record of what METIS saved.
  Eigen::SimplicialLDLT<SparseMatrix, Eigen::Lower, Eigen::AMDOrdering<int>> amd(cube);
  const auto amd_entries = amd.matrixL().nestedExpression().nonZeros();
  EXPECT_LE(static_cast<double>(f.factor_nonzeros()), kMetisSaving * amd_entries)
      << f.factor_nonzeros() << " against AMD's " << amd_entries;

  SparseFactorization small;
  ASSERT_TRUE(small.factor(cube_matrix(12)));  // 1,728 unknowns
  EXPECT_EQ(small.ordering(), SparseOrdering::amd);
  SparseFactorization diagonal;
  ASSERT_TRUE(diagonal.factor(sparse(Eigen::MatrixXd::Identity(4, 4))));
  EXPECT_EQ(diagonal.ordering(), SparseOrdering::none);
  EXPECT_EQ(ordering_name(SparseOrdering::metis), "metis");
}

// Two masses m joined by a spring k, flying at v0 toward a wall at `gap` from the second one.
// At the impact the second node stops (the Lagrange multiplier's impulse); then it stays on the
// wall while the first compresses the spring: λ = k·(u1 − u2) = v0·√(k·m)·sin(ω·s), ω = √(k/m),
// s the time since the impact, until s = π/ω, when the first node moves back at −v0 and the
// spring releases the second.
struct TwoMasses {
  double m = 2.0, k = 800.0, v0 = 3.0, gap = 0.3;
  double omega() const { return std::sqrt(k / m); }
  double impact() const { return gap / v0; }
  double lambda(double t) const {
    const double s = t - impact();
    return s > 0.0 && s < kPi / omega() ? v0 * std::sqrt(k * m) * std::sin(omega() * s) : 0.0;
  }
  /// Both at rest relative to each other, flying at v0; the contact force zero.
  State start() const {
    State s;
    s.u = Eigen::Vector2d::Zero();
    s.v = Eigen::Vector2d::Constant(v0);
    s.a = Eigen::Vector2d::Zero();
    s.multipliers = Eigen::VectorXd::Zero(1);
    return s;
  }
  SparseSystem system() const {
    SparseSystem out;
    out.mass = sparse(Eigen::Matrix2d{{m, 0.0}, {0.0, m}});
    out.stiffness = sparse(Eigen::Matrix2d{{k, -k}, {-k, k}});
    out.damping = SparseMatrix(2, 2);
    out.constraints = {{1, -1, gap}};
    return out;
  }
};

// The same two masses as a tridiagonal system (a chain), for the tridiagonal integrators.
SecondOrderSystem as_chain(const SparseSystem& system) {
  SecondOrderSystem chain;
  chain.mass = *as_tridiagonal(system.mass);
  chain.stiffness = *as_tridiagonal(system.stiffness);
  chain.damping = Tridiagonal::zero(system.size());
  chain.constraints = system.constraints;
  return chain;
}

// The implicit family does not stop the node at the impact (a position constraint at the end of
// the step reverses its velocity: the spurious oscillations the paper counts), so the closed form
// is central difference's test below; here the Signorini conditions at every step, and the same
// numbers as the tridiagonal integrator with the same constraint (2 DOFs: a chain).
TEST(SparseImplicitIntegrator, TwoMassesOnAWallKeepTheContactConditionsAsTheChainIntegrator) {
  const TwoMasses model;
  const SparseSystem system = model.system();
  const SecondOrderSystem chain = as_chain(system);
  const double dt = (kPi / model.omega()) / 400.0;
  const ImplicitCoefficients c = implicit_coefficients(HhtParams{.alpha = -0.3});
  SparseImplicitIntegrator stepper;
  ImplicitIntegrator reference;
  ASSERT_TRUE(stepper.initialize(system, c, dt));
  ASSERT_TRUE(reference.initialize(chain, c, dt));
  State s = model.start();
  State r = s;
  int active = 0;
  const double end = model.impact() + 3.0 * kPi / model.omega();
  while (s.t < end) {
    stepper.step(system, s);
    reference.step(chain, r);
    ASSERT_GE(s.multipliers[0], 0.0);
    ASSERT_LE(s.u[1], model.gap);
    if (s.multipliers[0] > 0.0) {
      ++active;
      EXPECT_EQ(s.u[1], model.gap);  // complementarity: exactly on the wall while pushed
    }
    ASSERT_NEAR(s.u[0], r.u[0], 1e-12 * model.gap) << "t = " << s.t;
    ASSERT_NEAR(s.multipliers[0], r.multipliers[0], 1e-9 * model.v0 * std::sqrt(model.k * model.m));
  }
  EXPECT_GT(active, 0);
}

TEST(SparseCentralDifference, TwoMassesOnAWallFollowTheClosedForm) {
  const TwoMasses model;
  const SparseSystem system = model.system();
  const double dt = (kPi / model.omega()) / 4000.0;
  State s = model.start();
  SparseCentralDifference stepper;
  ASSERT_TRUE(stepper.initialize(system, CdmVelocity::central, dt, s));
  const double peak = model.v0 * std::sqrt(model.k * model.m);
  double worst = 0.0;
  const double end = model.impact() + 1.5 * kPi / model.omega();
  while (s.t < end) {
    stepper.step(system, s);
    ASSERT_GE(s.multipliers[0], 0.0);
    ASSERT_LE(s.u[1], model.gap);
    const double since = s.t - model.impact();
    if (since > 20 * dt && std::abs(since - kPi / model.omega()) > 20 * dt) {
      worst = std::max(worst, std::abs(s.multipliers[0] - model.lambda(s.t)));
    }
  }
  EXPECT_LT(worst, 2e-3 * peak);
}

TEST(SparseCentralDifference, RefusesAConsistentMass) {
  SparseSystem system = TwoMasses{}.system();
  system.mass = sparse(Eigen::Matrix2d{{2.0, 1.0}, {1.0, 2.0}});
  State s;
  s.u = s.v = s.a = Eigen::Vector2d::Zero();
  SparseCentralDifference stepper;
  EXPECT_FALSE(stepper.initialize(system, CdmVelocity::central, 1e-3, s));
  EXPECT_NE(stepper.failure().find("diagonal (lumped) mass"), std::string::npos)
      << stepper.failure();
}

// The paper's rod as a sparse system against the tridiagonal integrators with the same
// constraint list: the same formulas with another factorisation, so equal to round-off. Over the
// whole run only without contact: the contact node chatters on the wall, and which of two
// round-off-close predictions penetrates decides a step's multiplier, so with contact the runs
// are compared over the impact's first steps.
void expect_sparse_equals_tridiagonal(MassMatrix mass, const MethodParams& method, bool contact) {
  RodScene rod;
  rod.mass = mass;
  rod.elements = 100;
  rod.rayleigh_stiffness = 1e-8;
  SecondOrderSystem tri = assemble_rod(rod);
  const Eigen::Index n = tri.size();
  tri.constraints = {{n - 1, -1, contact ? rod.gap : 1e9}};
  tri.gap = std::numeric_limits<double>::infinity();
  SparseSystem sys;
  sys.mass = to_sparse(tri.mass);
  sys.stiffness = to_sparse(tri.stiffness);
  sys.damping = to_sparse(tri.damping);
  sys.constraints = tri.constraints;
  const RodSceneDerived d = derive(rod);

  State a, b;
  // Without contact, a displaced start (half a sine) so that the rod vibrates.
  a.u = contact ? Eigen::VectorXd::Zero(n)
                : Eigen::VectorXd(0.01 * Eigen::ArrayXd::LinSpaced(n, 0.0, kPi).sin());
  a.v = Eigen::VectorXd::Constant(n, rod.velocity);
  a.multipliers = Eigen::VectorXd::Zero(1);
  a.a = consistent_acceleration(tri, a);
  b = a;
  const ImplicitCoefficients c = implicit_coefficients(method);
  ImplicitIntegrator x;
  SparseImplicitIntegrator y;
  ASSERT_TRUE(x.initialize(tri, c, d.time_step));
  ASSERT_TRUE(y.initialize(sys, c, d.time_step));
  const long steps = contact ? static_cast<long>(d.impact_time / d.time_step) + 40 : d.step_count;
  double worst_u = 0.0, worst_lambda = 0.0, largest_u = 0.0;
  for (long i = 0; i < steps; ++i) {
    x.step(tri, a);
    y.step(sys, b);
    worst_u = std::max(worst_u, (a.u - b.u).lpNorm<Eigen::Infinity>());
    largest_u = std::max(largest_u, a.u.lpNorm<Eigen::Infinity>());
    worst_lambda = std::max(worst_lambda, std::abs(a.multipliers[0] - b.multipliers[0]));
  }
  EXPECT_LT(worst_u, 1e-11 * largest_u) << to_string(mass) << (contact ? " contact" : "");
  EXPECT_LT(worst_lambda / rod.area, 1e-9 * d.pressure_scale) << to_string(mass);
}

TEST(SparseImplicitIntegrator, EqualsTheTridiagonalIntegratorOnTheRod) {
  for (const bool contact : {false, true}) {
    expect_sparse_equals_tridiagonal(MassMatrix::lumped, HhtParams{.alpha = -0.1}, contact);
    expect_sparse_equals_tridiagonal(MassMatrix::consistent, HhtParams{.alpha = -0.2}, contact);
    expect_sparse_equals_tridiagonal(MassMatrix::consistent, GeneralizedAlphaParams{.rho_inf = 0.5},
                                     contact);
  }
}

TEST(ContactLcp, AnySizeSolverEqualsTheFixedOneBitForBit) {
  std::mt19937 rng(7);
  std::normal_distribution<double> normal;
  std::uniform_int_distribution<int> size(1, kMaxConstraints);
  ContactLcpWorkspace w;
  w.resize(kMaxConstraints);
  for (int trial = 0; trial < 500; ++trial) {
    const int m = size(rng);
    Eigen::MatrixXd b(m, m);
    for (int i = 0; i < m; ++i) {
      for (int j = 0; j < m; ++j) b(i, j) = normal(rng);
    }
    const Eigen::MatrixXd d = b * b.transpose() + 0.1 * Eigen::MatrixXd::Identity(m, m);
    Eigen::VectorXd p(m);
    for (int k = 0; k < m; ++k) p[k] = normal(rng);
    Eigen::VectorXd x(m), y(m);
    const int fx = solve_contact_lcp(d.data(), p.data(), m, x.data());
    const int fy = solve_contact_lcp(d.data(), p.data(), m, y.data(), w);
    ASSERT_EQ(fx, fy);
    for (int k = 0; k < m; ++k) ASSERT_EQ(x[k], y[k]) << trial;
  }
}

TEST(ContactLcp, SolvesAHundredCoupledConstraints) {
  // A block's bottom edge: 100 contacts coupled through the body (a dense SPD Delassus matrix).
  std::mt19937 rng(11);
  std::normal_distribution<double> normal;
  const int m = 100;
  Eigen::MatrixXd b(m, m);
  for (int i = 0; i < m; ++i) {
    for (int j = 0; j < m; ++j) b(i, j) = normal(rng);
  }
  const Eigen::MatrixXd d = b * b.transpose() / m + 0.05 * Eigen::MatrixXd::Identity(m, m);
  ContactLcpWorkspace w;
  w.resize(m);
  for (int trial = 0; trial < 20; ++trial) {
    Eigen::VectorXd p(m), mu(m);
    for (int k = 0; k < m; ++k) p[k] = normal(rng);
    solve_contact_lcp(d.data(), p.data(), m, mu.data(), w);
    const Eigen::VectorXd g = p - d * mu;
    const double scale = p.cwiseAbs().maxCoeff();
    for (int k = 0; k < m; ++k) {
      ASSERT_GE(mu[k], 0.0);
      ASSERT_LE(g[k], 1e-9 * scale) << "constraint " << k << " penetrates";
      ASSERT_LE(std::abs(mu[k] * g[k]), 1e-9 * scale * mu.cwiseAbs().maxCoeff());
    }
  }
}

// A tridiagonal model with one upper wall runs the built-in rod's operations; the same model
// with a general pattern (an explicit zero beyond the band is not a pattern: a real entry is)
// runs the sparse integrators.
TEST(ModelScene, ChoosesTheTridiagonalPathForAChainAndTheSparseOneOtherwise) {
  auto model = std::make_shared<Model>();
  const TwoMasses two;
  const SparseSystem s = two.system();
  model->mass = s.mass;
  model->stiffness = s.stiffness;
  model->initial_velocity = Eigen::Vector2d::Constant(two.v0);
  model->initial_displacement = Eigen::Vector2d::Zero();
  model->contacts = {{"wall", 1, -1, two.gap, 1.0, 1}};
  ModelScene scene{model, 1e-4, 0.5};
  const AssembledScene chain = assemble(scene);
  EXPECT_FALSE(chain.sparse);
  EXPECT_EQ(chain.system.contact_dof, 1);
  EXPECT_TRUE(chain.rigid_flight);
  EXPECT_DOUBLE_EQ(chain.first_contact_time, two.gap / two.v0);

  // Three masses in a triangle of springs: K has an entry beyond the band.
  auto triangle = std::make_shared<Model>(*model);
  Eigen::Matrix3d k{{2, -1, -1}, {-1, 2, -1}, {-1, -1, 2}};
  triangle->mass = sparse(Eigen::Matrix3d::Identity());
  triangle->stiffness = sparse(100.0 * k);
  triangle->initial_velocity = Eigen::Vector3d::Constant(1.0);
  triangle->initial_displacement = Eigen::Vector3d::Zero();
  scene.model = triangle;
  const AssembledScene general = assemble(scene);
  ASSERT_TRUE(general.sparse);
  EXPECT_EQ(general.sparse->constraints.size(), 1u);
  SimulationWorkspace ws;
  // A third of the mass on the contact DOF: the impact's velocity reversal (see above) changes
  // the energy much more than on a rod's end node; the bound is not this test's subject.
  const RunSummary run =
      simulate(general, HhtParams{.alpha = -0.1}, RunOptions{.energy_growth_limit = 1e3}, ws);
  EXPECT_EQ(run.status, RunStatus::ok) << run.message;
  EXPECT_GT(*std::max_element(ws.trace.pressure.begin(), ws.trace.pressure.end()), 0.0);
  EXPECT_LE(run.max_penetration, 1e-12);
}

// The penalty and augmented-Lagrangian laws on a sparse model
// (core/methods/sparse_integrators.hpp): the same numbers as the tridiagonal integrator's
// constraint list with the same springs, and the penalty's force is the spring of the step's end, λ
// = k·max(0, g), at every step.
TEST(SparseImplicitIntegrator, PenaltyAndAugmentedLagrangianAsTheChainIntegrator) {
  const TwoMasses model;
  const SparseSystem system = model.system();
  const SecondOrderSystem chain = as_chain(system);
  const double dt = (kPi / model.omega()) / 400.0;
  const ImplicitCoefficients c = implicit_coefficients(HhtParams{.alpha = -0.3});
  const double impulse_scale = model.v0 * std::sqrt(model.k * model.m);
  for (const ContactLaw law : {ContactLaw::penalty, ContactLaw::augmented_lagrangian}) {
    SCOPED_TRACE(to_string(law));
    // Uzawa's error shrinks by 1/(1 + w·k·d) per iteration (d ≈ Δt²/m here): a stiff spring.
    const double factor = law == ContactLaw::penalty ? 3.0 : 1e5;
    const ContactTreatment treatment{.law = law,
                                     .penalty_factor = factor,
                                     .augmented_tolerance = 1e-9,
                                     .augmented_max_iterations = 1000};
    const ContactPenalties sparse_contact = resolve_contact(treatment, system);
    const ContactPenalties chain_contact = resolve_contact(treatment, chain);
    ASSERT_EQ(sparse_contact.listed.size(), 1u);
    EXPECT_EQ(sparse_contact.listed, chain_contact.listed);
    EXPECT_EQ(sparse_contact.listed[0], factor * model.k);  // K's diagonal at the contact DOF
    SparseImplicitIntegrator stepper;
    ImplicitIntegrator reference;
    ASSERT_TRUE(stepper.initialize(system, c, dt, sparse_contact));
    ASSERT_TRUE(reference.initialize(chain, c, dt, chain_contact));
    State s = model.start();
    State r = s;
    int active = 0;
    double deepest = 0.0;
    const double end = model.impact() + 3.0 * kPi / model.omega();
    while (s.t < end) {
      stepper.step(system, s);
      reference.step(chain, r);
      const double penetration = s.u[1] - model.gap;
      ASSERT_GE(s.multipliers[0], 0.0);
      if (law == ContactLaw::penalty) {
        EXPECT_NEAR(s.multipliers[0], 3.0 * model.k * std::max(0.0, penetration),
                    1e-9 * impulse_scale)
            << "t = " << s.t;
      } else {
        EXPECT_LE(penetration, 1e-9 * model.gap) << "t = " << s.t;
      }
      active += s.multipliers[0] > 0.0;
      deepest = std::max(deepest, penetration);
      ASSERT_NEAR(s.u[0], r.u[0], 1e-12 * model.gap) << "t = " << s.t;
      ASSERT_NEAR(s.multipliers[0], r.multipliers[0], 1e-9 * impulse_scale) << "t = " << s.t;
    }
    EXPECT_GT(active, 0);
    if (law == ContactLaw::penalty) {
      EXPECT_GT(deepest, 0.0);
    }
    EXPECT_EQ(stepper.contact_iterations(), reference.contact_iterations());
    EXPECT_EQ(stepper.unconverged_contact_steps(), 0);
    if (law == ContactLaw::augmented_lagrangian) {
      EXPECT_GT(stepper.contact_iterations(), 0);
    }
  }
}

// Through simulate() on a model that only the sparse path takes (K beyond the band): every
// implicit method runs the penalty and augmented-Lagrangian laws with λ >= 0 at every sample;
// the penalty leaves the node in the wall, the augmented Lagrangian within its tolerance of
// Lagrange's; so does central difference, with its stable step under the penalty.
TEST(ModelScene, SparseModelsTakeThePenaltyAndAugmentedLagrangianLaws) {
  auto triangle = std::make_shared<Model>();
  const Eigen::Matrix3d k{{2, -1, -1}, {-1, 2, -1}, {-1, -1, 2}};
  triangle->mass = sparse(Eigen::Matrix3d::Identity());
  triangle->stiffness = sparse(100.0 * k);
  triangle->initial_velocity = Eigen::Vector3d::Constant(1.0);
  triangle->initial_displacement = Eigen::Vector3d::Zero();
  triangle->contacts = {{"wall", 1, -1, 0.3, 1.0, 1}};
  const AssembledScene scene = assemble(ModelScene{triangle, 1e-3, 2.0});
  ASSERT_TRUE(scene.sparse);
  const RunOptions base{.energy_growth_limit = 1e3};
  for (const auto& [name, method] :
       std::vector<std::pair<const char*, MethodParams>>{{"hht", HhtParams{.alpha = -0.1}},
                                                         {"rho-bathe", RhoBatheParams{}},
                                                         {"houbolt", HouboltParams{}}}) {
    SCOPED_TRACE(name);
    SimulationWorkspace ws;
    const RunSummary lagrange = simulate(scene, method, base, ws);
    ASSERT_EQ(lagrange.status, RunStatus::ok) << lagrange.message;
    const std::vector<double> lagrange_pressure = ws.trace.pressure;

    RunOptions penalty = base;
    penalty.contact = {.law = ContactLaw::penalty, .penalty_factor = 10.0};
    const RunSummary p = simulate(scene, method, penalty, ws);
    ASSERT_EQ(p.status, RunStatus::ok) << p.message;
    EXPECT_GT(p.max_penetration, 0.0);
    for (const double pressure : ws.trace.pressure) ASSERT_GE(pressure, 0.0);

    RunOptions augmented = base;
    // A stiff spring: Uzawa's error shrinks by 1/(1 + w·k·d) per iteration, d ≈ Δt²/m.
    augmented.contact = {.law = ContactLaw::augmented_lagrangian,
                         .penalty_factor = 1e6,
                         .augmented_tolerance = 1e-12,
                         .augmented_max_iterations = 1000};
    const RunSummary al = simulate(scene, method, augmented, ws);
    ASSERT_EQ(al.status, RunStatus::ok) << al.message;
    EXPECT_GT(al.contact_iterations, 0);
    EXPECT_EQ(al.unconverged_contact_steps, 0);
    EXPECT_LT(al.max_penetration, 1e-8 * 0.3);
    ASSERT_EQ(ws.trace.pressure.size(), lagrange_pressure.size());
    const double scale = *std::max_element(lagrange_pressure.begin(), lagrange_pressure.end());
    for (std::size_t i = 0; i < lagrange_pressure.size(); ++i) {
      ASSERT_NEAR(ws.trace.pressure[i], lagrange_pressure[i], 1e-6 * scale) << "sample " << i;
    }
  }
  // Central difference: the explicit penalty within its stable step with the spring (M = I, K's
  // row sums 400, the spring f·K_11 = 200·f on DOF 1: ω_bound² = 400 + 200·f), reported; above
  // it the run is flagged before it starts.
  SimulationWorkspace ws;
  const RunSummary lagrange = simulate(scene, CentralDifferenceParams{}, base, ws);
  ASSERT_EQ(lagrange.status, RunStatus::ok) << lagrange.message;
  EXPECT_NEAR(lagrange.stable_dt, 2.0 / std::sqrt(400.0), 1e-15);
  const std::vector<double> lagrange_pressure = ws.trace.pressure;
  RunOptions penalty = base;
  penalty.contact = {.law = ContactLaw::penalty, .penalty_factor = 10.0};
  const RunSummary cdm = simulate(scene, CentralDifferenceParams{}, penalty, ws);
  ASSERT_EQ(cdm.status, RunStatus::ok) << cdm.message;
  EXPECT_TRUE(cdm.warning.empty()) << cdm.warning;
  EXPECT_NEAR(cdm.stable_dt, 2.0 / std::sqrt(400.0 + 2000.0), 1e-15);
  EXPECT_GT(cdm.max_penetration, 0.0);
  for (const double pressure : ws.trace.pressure) ASSERT_GE(pressure, 0.0);
  penalty.contact.penalty_factor = 1e5;  // stable step 4.5e-4 s < Δt = 1e-3 s
  const RunSummary flagged = simulate(scene, CentralDifferenceParams{}, penalty, ws);
  EXPECT_NEAR(flagged.stable_dt, 2.0 / std::sqrt(400.0 + 2e7), 1e-15);
  EXPECT_NE(flagged.warning.find("exceeds central difference's stable step with the penalty "
                                 "springs"),
            std::string::npos)
      << flagged.warning;
  RunOptions augmented = base;
  augmented.contact = {.law = ContactLaw::augmented_lagrangian,
                       .penalty_factor = 1e3,
                       .augmented_tolerance = 1e-12,
                       .augmented_max_iterations = 1000};
  const RunSummary al = simulate(scene, CentralDifferenceParams{}, augmented, ws);
  ASSERT_EQ(al.status, RunStatus::ok) << al.message;
  EXPECT_GT(al.contact_iterations, 0);
  EXPECT_EQ(al.unconverged_contact_steps, 0);
  EXPECT_LT(al.max_penetration, 1e-8 * 0.3);
  const double scale = *std::max_element(lagrange_pressure.begin(), lagrange_pressure.end());
  for (std::size_t i = 0; i < lagrange_pressure.size(); ++i) {
    ASSERT_NEAR(ws.trace.pressure[i], lagrange_pressure[i], 1e-6 * scale) << "sample " << i;
  }
}

// Central difference on a sparse model under the penalty and augmented-Lagrangian laws: the same
// numbers as the tridiagonal central difference's constraint list with the same springs, the
// penalty's force the spring of u_t, λ_t = k·max(0, g(u_t)), at every step, and the same stable
// step with the spring, 2/√((2 + f)·k/m).
TEST(SparseCentralDifference, PenaltyAndAugmentedLagrangianAsTheChainCentralDifference) {
  const TwoMasses model;
  const SparseSystem system = model.system();
  const SecondOrderSystem chain = as_chain(system);
  const double dt = (kPi / model.omega()) / 400.0;
  const double impulse_scale = model.v0 * std::sqrt(model.k * model.m);
  for (const ContactLaw law : {ContactLaw::penalty, ContactLaw::augmented_lagrangian}) {
    SCOPED_TRACE(to_string(law));
    // Uzawa's error shrinks by 1/(1 + k·Δt²/m) per iteration: a stiff spring for the augmented
    // Lagrangian (its force is not explicit: no stable step to mind).
    const double factor = law == ContactLaw::penalty ? 3.0 : 1e4;
    const ContactTreatment treatment{.law = law,
                                     .penalty_factor = factor,
                                     .augmented_tolerance = 1e-9,
                                     .augmented_max_iterations = 1000};
    const ContactPenalties sparse_contact = resolve_contact(treatment, system);
    const ContactPenalties chain_contact = resolve_contact(treatment, chain);
    State s = model.start();
    State r = s;
    SparseCentralDifference stepper;
    CentralDifference reference;
    ASSERT_TRUE(stepper.initialize(system, CdmVelocity::central, dt, s, sparse_contact));
    ASSERT_TRUE(reference.initialize(chain, CdmVelocity::central, dt, r, chain_contact));
    EXPECT_NEAR(stepper.stable_step(), reference.stable_step(), 1e-15);
    if (law == ContactLaw::penalty) {
      EXPECT_NEAR(stepper.stable_step(), 2.0 / std::sqrt((2.0 + factor) * model.k / model.m),
                  1e-15);
    }
    int active = 0;
    const double end = model.impact() + 3.0 * kPi / model.omega();
    while (s.t < end) {
      stepper.step(system, s);
      reference.step(chain, r);
      ASSERT_GE(s.multipliers[0], 0.0);
      const double penetration = s.u[1] - model.gap;
      if (law == ContactLaw::penalty) {
        ASSERT_NEAR(s.multipliers[0], factor * model.k * std::max(0.0, penetration),
                    1e-9 * impulse_scale)
            << "t = " << s.t;
      } else {
        ASSERT_LE(penetration, 1e-9 * model.gap) << "t = " << s.t;
      }
      active += s.multipliers[0] > 0.0;
      ASSERT_NEAR(s.u[0], r.u[0], 1e-12 * model.gap) << "t = " << s.t;
      ASSERT_NEAR(s.multipliers[0], r.multipliers[0], 1e-9 * impulse_scale) << "t = " << s.t;
    }
    EXPECT_GT(active, 0);
    EXPECT_EQ(stepper.contact_iterations(), reference.contact_iterations());
    if (law == ContactLaw::augmented_lagrangian) {
      EXPECT_GT(stepper.contact_iterations(), 0);
    }
    EXPECT_EQ(stepper.unconverged_contact_steps(), 0);
  }
}

}  // namespace
}  // namespace impactid
