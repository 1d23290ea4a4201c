// The warning an explicit stage scheme's run (Noh–Bathe's, core/methods/noh_bathe.hpp; Kim's,
// core/methods/kim_explicit.hpp) gets before it starts when its step exceeds the scheme's stable
// step: the run still goes, and the energy bound stops it if it blows up (as central difference's).
// simulate() (core/run/simulation.cpp) and the batched kernel (core/batch/explicit_stage.hpp) both
// report it, so that a batched lane's summary equals the scalar run's bit for bit.
//
// Thread safety: a pure function.
#pragma once

#include <string>
#include <string_view>

#include "core/common/parameter_error.hpp"
#include "core/contact/contact_treatment.hpp"

namespace impactid {

/// "dt = … s exceeds <method>'s stable step … s (Omega_crit = … at p = …)" and what to lower (the
/// step; with the penalty law also its stiffness, whose springs shorten the stable step); "" when
/// the stepper is within its stable step or certifies none (stable_step() 0: a mass that is not
/// diagonal). `stepper`: NohBatheExplicit or KimExplicit after initialize(), at step `dt` [s];
/// `critical_omega`: the scheme's Ω_crit(p).
template <class Stepper>
std::string stable_step_warning(const Stepper& stepper, std::string_view method, double p,
                                double critical_omega, double dt, ContactLaw law) {
  if (stepper.within_stability_limit() || !(stepper.stable_step() > 0.0)) return {};
  return "dt = " + format_value(dt) + " s exceeds " + std::string(method) + "'s stable step " +
         format_value(stepper.stable_step()) + " s (Omega_crit = " + format_value(critical_omega) +
         " at p = " + format_value(p) + ")" +
         (law == ContactLaw::penalty
              ? " with the penalty springs: lower the step or the penalty stiffness"
              : ": lower the step");
}

}  // namespace impactid
