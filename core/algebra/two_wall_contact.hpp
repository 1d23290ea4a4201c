// The contact problem of one step with two unilateral constraints, one at each end of the rod
// (the repeated-impact scene: the main wall at the contact dof, the far wall at node 0).
//
// After a contact-free prediction the two contact dofs penetrate their walls by p_main and p_far
// (positive = penetration). Contact forces μ >= 0 (weighted multipliers; the main one pushes its
// dof back by −μ_main, the far one by +μ_far) change the penetrations linearly:
//   g_main = p_main − d_main·μ_main + c_main_far·μ_far
//   g_far  = p_far  + c_far_main·μ_main − d_far·μ_far
// with d = (influence of a force on its own dof) and c = (on the other dof), from the columns
// A⁻¹e_main and A⁻¹e_far of the step's effective matrix (times b1·Δt² for the implicit methods,
// 1 for central difference). The Signorini conditions g <= 0, μ >= 0, g·μ = 0 form a 2×2 linear
// complementarity problem; its matrix is positive definite (A is), so exactly one of the four
// active sets holds, and it is found here by trying them in turn: O(1), no allocation.
//
// The main-only branch computes μ_main = p_main / d_main exactly as the single-contact code
// does, so a far wall that is never reached changes no bit of a run.
//
// Thread safety: a pure function.
#pragma once

namespace impactid {

struct TwoWallForces {
  double main = 0.0;  ///< weighted force at the main (contact) dof, >= 0
  double far = 0.0;   ///< weighted force at the far dof, >= 0
};

/// Solves the 2×2 complementarity problem above. d_main, d_far > 0; d_main·d_far > c·c.
inline TwoWallForces solve_two_wall_contact(double p_main, double p_far, double d_main,
                                            double d_far, double c_main_far, double c_far_main) {
  const bool main_penetrates = p_main > 0.0, far_penetrates = p_far > 0.0;
  if (!main_penetrates && !far_penetrates) return {};
  if (main_penetrates) {
    const double main = p_main / d_main;
    if (p_far + c_far_main * main <= 0.0) return {main, 0.0};
  }
  if (far_penetrates) {
    const double far = p_far / d_far;
    if (p_main + c_main_far * far <= 0.0) return {0.0, far};
  }
  // Both walls active: d_main·μ_main − c_main_far·μ_far = p_main,
  //                    −c_far_main·μ_main + d_far·μ_far = p_far.
  const double det = d_main * d_far - c_main_far * c_far_main;
  const double main = (d_far * p_main + c_main_far * p_far) / det;
  const double far = (d_main * p_far + c_far_main * p_main) / det;
  // In exact arithmetic one of the four sets holds; at the border between two of them round-off
  // can reject both single-wall sets and leave a component here a few ulps below zero, where
  // the adjacent set's answer (that force zero) is the solution.
  return {main > 0.0 ? main : 0.0, far > 0.0 ? far : 0.0};
}

}  // namespace impactid
