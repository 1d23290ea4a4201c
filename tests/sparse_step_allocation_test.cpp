// The sparse integrators' step allocates nothing (issue 20: "per step O(nnz(L)) work, no
// allocation"): every call to malloc, calloc, realloc and operator new in this executable is
// counted while the steps run. malloc and its kin are wrapped at link time (-Wl,--wrap, see
// tests/CMakeLists.txt), which reaches Eigen's allocations inlined into the core library too.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <new>

#include "core/methods/houbolt.hpp"
#include "core/methods/kim_explicit.hpp"
#include "core/methods/kr_alpha.hpp"
#include "core/methods/noh_bathe.hpp"
#include "core/methods/sparse_integrators.hpp"
#include "core/methods/sparse_kr_alpha.hpp"
#include "core/methods/wilson_theta.hpp"
#include "core/model/model_scene.hpp"
#include "core/model/scene_assembly.hpp"
#include "study/plan/plan.hpp"
#include "study/plan/simulation_settings.hpp"

namespace {
std::atomic<bool> counting{false};
std::atomic<long> allocations{0};
void count() {
  if (counting.load(std::memory_order_relaxed)) allocations.fetch_add(1);
}
}  // namespace

extern "C" {
void* __real_malloc(std::size_t size);
void* __real_calloc(std::size_t count, std::size_t size);
void* __real_realloc(void* pointer, std::size_t size);
void* __wrap_malloc(std::size_t size) {
  count();
  return __real_malloc(size);
}
void* __wrap_calloc(std::size_t n, std::size_t size) {
  count();
  return __real_calloc(n, size);
}
void* __wrap_realloc(void* pointer, std::size_t size) {
  count();
  return __real_realloc(pointer, size);
}
}

void* operator new(std::size_t size) {
  count();
  if (void* p = __real_malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
// GCC 12 warns that free() gets a pointer from operator new; this operator new is malloc's.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}
#pragma GCC diagnostic pop

namespace impactid {
namespace {

TEST(SparseStep, AllocatesNothingOnTheBlock) {
  const Simulation sim = std::get<Simulation>(build(
      load_scene_file(std::filesystem::path(IMPACTID_SOURCE_DIR) / "examples/block/scene.toml")));
  const AssembledScene scene = assemble(*sim.model());
  ASSERT_TRUE(scene.sparse);
  const SparseSystem& system = *scene.sparse;
  for (const bool cdm : {false, true}) {
    for (const ContactLaw law :
         {ContactLaw::lagrange, ContactLaw::penalty, ContactLaw::augmented_lagrangian}) {
      // The penalty and augmented-Lagrangian laws too: their contact problems and Uzawa's
      // iterations use storage sized by initialize().
      const ContactPenalties contact = resolve_contact({.law = law}, system);
      State s;
      s.u = Eigen::VectorXd::Zero(system.size());
      s.v = scene.initial_velocity;
      s.a = Eigen::VectorXd::Zero(system.size());
      s.multipliers = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(system.constraints.size()));
      SparseImplicitIntegrator implicit;
      SparseCentralDifference explicit_;
      // The set-up allocates, inside the core library: the counter sees the library's calls.
      allocations = 0;
      counting = true;
      ASSERT_TRUE(cdm ? explicit_.initialize(system, CdmVelocity::central, scene.dt, s, contact)
                      : implicit.initialize(system, implicit_coefficients(HhtParams{.alpha = -0.1}),
                                            scene.dt, contact));
      counting = false;
      EXPECT_GT(allocations.load(), 0);
      const auto step = [&] {
        if (cdm) {
          explicit_.step(system, s);
        } else {
          implicit.step(system, s);
        }
      };
      step();  // a first step may size scratch storage
      allocations = 0;
      counting = true;
      // Through the impact: the steps with contact forces and the contact problem are included.
      double largest = 0.0;
      for (long i = 1; i < scene.step_count; ++i) {
        step();
        largest = std::max(largest, s.multipliers.maxCoeff());
      }
      counting = false;
      EXPECT_EQ(allocations.load(), 0) << (cdm ? "central difference " : "hht ") << to_string(law);
      EXPECT_GT(largest, 0.0) << to_string(law);  // the run did reach the plane
      if (law == ContactLaw::augmented_lagrangian) {
        EXPECT_GT(cdm ? explicit_.contact_iterations() : implicit.contact_iterations(), 0);
      }
    }
  }
}

// Houbolt and Wilson-θ drive the same integrators and allocate nothing either, once their first
// steps have sized their own storage (Houbolt's past displacements fill over its three kinds of
// step).
TEST(SparseStep, HouboltAndWilsonThetaAllocateNothingOnTheBlock) {
  const Simulation sim = std::get<Simulation>(build(
      load_scene_file(std::filesystem::path(IMPACTID_SOURCE_DIR) / "examples/block/scene.toml")));
  const AssembledScene scene = assemble(*sim.model());
  ASSERT_TRUE(scene.sparse);
  const SparseSystem& system = *scene.sparse;
  for (const bool houbolt : {true, false}) {
    State s;
    s.u = Eigen::VectorXd::Zero(system.size());
    s.v = scene.initial_velocity;
    s.a = Eigen::VectorXd::Zero(system.size());
    s.multipliers = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(system.constraints.size()));
    Houbolt<SparseImplicitIntegrator, SparseSystem> h;
    WilsonTheta<SparseImplicitIntegrator, SparseSystem> w;
    ASSERT_TRUE(houbolt ? h.initialize(system, scene.dt)
                        : w.initialize(system, wilson_theta_coefficients({}), scene.dt));
    const auto step = [&] { houbolt ? h.step(system, s) : w.step(system, s); };
    for (int i = 0; i < 3; ++i) step();
    allocations = 0;
    counting = true;
    double largest = 0.0;
    for (long i = 3; i < scene.step_count; ++i) {
      step();
      largest = std::max(largest, s.multipliers.maxCoeff());
    }
    counting = false;
    EXPECT_EQ(allocations.load(), 0) << (houbolt ? "houbolt" : "wilson-theta");
    EXPECT_GT(largest, 0.0);
  }
}

// The Noh–Bathe explicit step allocates nothing either (on the tridiagonal systems here; on the
// block below), through the impact: the paper's rod, the rod between two walls and a scene of
// bodies (the constraint list's complementarity problem).
TEST(SparseStep, NohBatheAllocatesNothing) {
  RodScene two_walls;
  two_walls.far_gap = 0.005;
  two_walls.t_end = 3e-4;
  Scene bodies;
  bodies.bodies = {Body{.name = "striker", .velocity = 1000.0, .segments = {Segment{}}},
                   Body{.name = "target", .gap = 0.01, .segments = {Segment{}}}};
  bodies.right_wall = Wall{.gap = 0.01};
  for (const ContactLaw law :
       {ContactLaw::lagrange, ContactLaw::penalty, ContactLaw::augmented_lagrangian}) {
    for (const AssembledScene& scene :
         {assemble(RodScene{}), assemble(two_walls), assemble(bodies)}) {
      const SecondOrderSystem& system = scene.system;
      State s;
      s.u = Eigen::VectorXd::Zero(system.size());
      s.v = scene.initial_velocity;
      s.a = Eigen::VectorXd::Zero(system.size());
      s.multipliers = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(system.constraints.size()));
      NohBatheExplicit stepper;
      ASSERT_TRUE(stepper.initialize(system, noh_bathe_coefficients({}), scene.dt, s,
                                     resolve_contact({.law = law}, system)));
      allocations = 0;
      counting = true;
      double largest = 0.0;
      for (long i = 0; i < scene.step_count; ++i) {
        stepper.step(system, s);
        largest =
            std::max({largest, s.lambda, s.multipliers.size() ? s.multipliers.maxCoeff() : 0.0});
      }
      counting = false;
      EXPECT_EQ(allocations.load(), 0) << to_string(law);
      EXPECT_GT(largest, 0.0) << to_string(law);  // the run did reach a wall
    }
  }
}

// Kim's two-stage explicit step allocates nothing either, through the impact, at both ends of its
// range (at p = ½ the sample's own contact solve is skipped): the paper's rod, the rod between two
// walls and a scene of bodies.
TEST(SparseStep, KimExplicitAllocatesNothing) {
  RodScene two_walls;
  two_walls.far_gap = 0.005;
  two_walls.t_end = 3e-4;
  Scene bodies;
  bodies.bodies = {Body{.name = "striker", .velocity = 1000.0, .segments = {Segment{}}},
                   Body{.name = "target", .gap = 0.01, .segments = {Segment{}}}};
  bodies.right_wall = Wall{.gap = 0.01};
  for (const ContactLaw law :
       {ContactLaw::lagrange, ContactLaw::penalty, ContactLaw::augmented_lagrangian}) {
    for (const double p : {1.0 / 3.0, 0.5}) {
      for (const AssembledScene& scene :
           {assemble(RodScene{}), assemble(two_walls), assemble(bodies)}) {
        const SecondOrderSystem& system = scene.system;
        State s;
        s.u = Eigen::VectorXd::Zero(system.size());
        s.v = scene.initial_velocity;
        s.a = Eigen::VectorXd::Zero(system.size());
        s.multipliers = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(system.constraints.size()));
        KimExplicit stepper;
        ASSERT_TRUE(stepper.initialize(system, kim_explicit_coefficients({.p = p}), scene.dt, s,
                                       resolve_contact({.law = law}, system)));
        allocations = 0;
        counting = true;
        double largest = 0.0;
        for (long i = 0; i < scene.step_count; ++i) {
          stepper.step(system, s);
          largest =
              std::max({largest, s.lambda, s.multipliers.size() ? s.multipliers.maxCoeff() : 0.0});
        }
        counting = false;
        EXPECT_EQ(allocations.load(), 0) << p << " " << to_string(law);
        EXPECT_GT(largest, 0.0) << p << " " << to_string(law);
      }
    }
  }
}

// The KR-α explicit step allocates nothing either (on the tridiagonal systems here; on the block
// below): its solves and the contact on the same three scenes, and a consistent mass with
// damping.
TEST(SparseStep, KrAlphaAllocatesNothing) {
  RodScene two_walls;
  two_walls.far_gap = 0.005;
  two_walls.t_end = 3e-4;
  RodScene damped;
  damped.mass = MassMatrix::consistent;
  damped.rayleigh_stiffness = 1e-8;
  Scene bodies;
  bodies.bodies = {Body{.name = "striker", .velocity = 1000.0, .segments = {Segment{}}},
                   Body{.name = "target", .gap = 0.01, .segments = {Segment{}}}};
  bodies.right_wall = Wall{.gap = 0.01};
  for (const ContactLaw law : {ContactLaw::lagrange, ContactLaw::augmented_lagrangian}) {
    for (const AssembledScene& scene :
         {assemble(RodScene{}), assemble(two_walls), assemble(damped), assemble(bodies)}) {
      const SecondOrderSystem& system = scene.system;
      State s;
      s.u = Eigen::VectorXd::Zero(system.size());
      s.v = scene.initial_velocity;
      s.a = Eigen::VectorXd::Zero(system.size());
      s.multipliers = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(system.constraints.size()));
      KrAlphaExplicit stepper;
      ASSERT_TRUE(stepper.initialize(system, kr_alpha_coefficients({}), scene.dt, s,
                                     resolve_contact({.law = law}, system)));
      allocations = 0;
      counting = true;
      double largest = 0.0;
      for (long i = 0; i < scene.step_count; ++i) {
        stepper.step(system, s);
        largest =
            std::max({largest, s.lambda, s.multipliers.size() ? s.multipliers.maxCoeff() : 0.0});
      }
      counting = false;
      EXPECT_EQ(allocations.load(), 0) << to_string(law);
      EXPECT_GT(largest, 0.0) << to_string(law);  // the run did reach a wall
    }
  }
}

// The explicit schemes with stages or model-based matrices on the block (a sparse model: M's
// factorisation, the 41 contacts' complementarity problem, the solves a contact force takes),
// through the impact, under each law they take, with the lumped mass: Noh–Bathe, Kim's scheme at
// both ends of its range, KR-α.
TEST(SparseStep, SparseExplicitSchemesAllocateNothingOnTheBlock) {
  const Simulation sim = std::get<Simulation>(build(
      load_scene_file(std::filesystem::path(IMPACTID_SOURCE_DIR) / "examples/block/scene.toml")));
  const AssembledScene scene = assemble(*sim.model());
  ASSERT_TRUE(scene.sparse);
  const SparseSystem& system = *scene.sparse;
  for (const ContactLaw law :
       {ContactLaw::lagrange, ContactLaw::penalty, ContactLaw::augmented_lagrangian}) {
    const ContactPenalties contact = resolve_contact({.law = law}, system);
    for (int method = 0; method < 4; ++method) {
      State s;
      s.u = Eigen::VectorXd::Zero(system.size());
      s.v = scene.initial_velocity;
      s.a = Eigen::VectorXd::Zero(system.size());
      s.multipliers = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(system.constraints.size()));
      SparseNohBatheExplicit noh_bathe;
      SparseKimExplicit kim;
      SparseKrAlphaExplicit kr_alpha;
      switch (method) {
        case 0:
          ASSERT_TRUE(
              noh_bathe.initialize(system, noh_bathe_coefficients({}), scene.dt, s, contact));
          break;
        case 1:
        case 2:
          ASSERT_TRUE(kim.initialize(
              system, kim_explicit_coefficients({.p = method == 1 ? 0.5 : 1.0 / 3.0}), scene.dt, s,
              contact));
          break;
        default:
          ASSERT_TRUE(kr_alpha.initialize(system, kr_alpha_coefficients({}), scene.dt, s, contact))
              << kr_alpha.failure();
      }
      const auto step = [&] {
        if (method == 0) {
          noh_bathe.step(system, s);
        } else if (method < 3) {
          kim.step(system, s);
        } else {
          kr_alpha.step(system, s);
        }
      };
      allocations = 0;
      counting = true;
      double largest = 0.0;
      for (long i = 0; i < scene.step_count; ++i) {
        step();
        largest = std::max(largest, s.multipliers.maxCoeff());
      }
      counting = false;
      EXPECT_EQ(allocations.load(), 0) << method << " " << to_string(law);
      EXPECT_GT(largest, 0.0) << method << " " << to_string(law);  // the run did reach the plane
    }
  }
}

// The counter works: an allocation while counting is seen.
TEST(SparseStep, TheCounterSeesAnAllocation) {
  allocations = 0;
  counting = true;
  Eigen::VectorXd v(1000);
  v.setZero();
  counting = false;
  EXPECT_GT(allocations.load(), 0);
  EXPECT_EQ(v.sum(), 0.0);
}

}  // namespace
}  // namespace impactid
