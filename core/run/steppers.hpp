// The steppers of every method on one kind of system, so that simulate() dispatches a method
// once (core/run/simulation.cpp, run_method) whatever the system is. The schemes that are
// already one template over the system (the composite schemes, Houbolt, Wilson-θ, Noh–Bathe,
// Kim) take the system as a parameter here; the three that still have a class per system (the
// implicit family's integrator, central difference, KR-α: their headers say why) are named per
// system in StepperTypes, the one place where the two systems' steppers differ.
//
// Thread safety: one object per thread (every stepper holds scratch vectors).
#pragma once

#include "core/methods/bathe_composite.hpp"
#include "core/methods/central_difference.hpp"
#include "core/methods/houbolt.hpp"
#include "core/methods/implicit_integrator.hpp"
#include "core/methods/kim_explicit.hpp"
#include "core/methods/kr_alpha.hpp"
#include "core/methods/noh_bathe.hpp"
#include "core/methods/sparse_integrators.hpp"
#include "core/methods/sparse_kr_alpha.hpp"
#include "core/methods/wilson_theta.hpp"
#include "core/model/second_order_system.hpp"
#include "core/model/semi_discrete_system.hpp"
#include "core/model/sparse_system.hpp"

namespace impactid {

/// The stepper classes written once per system, and the explicit stages' contact; specialised
/// for each system below.
template <SemiDiscreteSystem System>
struct StepperTypes;

template <>
struct StepperTypes<SecondOrderSystem> {
  using Implicit = ImplicitIntegrator;
  using CentralDifference = impactid::CentralDifference;
  using KrAlpha = KrAlphaExplicit;
  using StageContact = ExplicitStageContact;
};

template <>
struct StepperTypes<SparseSystem> {
  using Implicit = SparseImplicitIntegrator;
  using CentralDifference = SparseCentralDifference;
  using KrAlpha = SparseKrAlphaExplicit;
  using StageContact = SparseExplicitStageContact;
};

/// One stepper of every method on a `System`, reused from run to run (after the first run of a
/// given size, further runs of that size allocate nothing in the step loop).
template <SemiDiscreteSystem System>
struct Steppers {
  using Types = StepperTypes<System>;
  typename Types::Implicit implicit;  ///< the single-step implicit family
  BatheComposite<typename Types::Implicit, System> composite;  ///< Bathe, ρ∞-Bathe
  typename Types::CentralDifference central_difference;
  Houbolt<typename Types::Implicit, System> houbolt;  ///< with its past displacements
  WilsonTheta<typename Types::Implicit, System> wilson_theta;
  NohBatheScheme<typename Types::StageContact, System> noh_bathe;
  KimScheme<typename Types::StageContact, System> kim_explicit;
  typename Types::KrAlpha kr_alpha;
};

}  // namespace impactid
