// The contact problem of one step with several unilateral constraints (scenes of several bodies,
// core/model/scene.hpp): after a contact-free prediction the constraints are violated by p_k
// (positive = penetration); contact forces μ_k >= 0 change the violations linearly through the
// Delassus matrix D = G·A⁻¹·Gᵀ (scaled by the method's b1·Δt², or 1 for central difference):
//   g = p − D·μ <= 0,   μ >= 0,   μ_k·g_k = 0.
// This is the linear complementarity problem LCP(−p, D). D is symmetric positive definite (A is,
// and the constraint rows of a chain are linearly independent: each contact brings a node of its
// own), hence a P-matrix, so the solution exists and is unique.
//
// Solved by Murty's least-index principal pivoting (K. G. Murty, "Note on a Bard-type scheme for
// solving the complementarity problem", Opsearch 11, 1974): keep an active set S, solve
// D_SS·μ_S = p_S with μ = 0 off S, and flip the lowest-numbered index that violates its sign
// condition (μ_k < 0 in S, g_k > 0 off S). For a P-matrix this visits no active set twice and
// ends at the solution after finitely many flips, whatever the start. The start is the set of
// penetrating constraints, which is the answer in the common case of contacts that do not
// interact within the step (lumped central difference, or contacts far apart), so usually one
// solve suffices. Round-off at the border between two active sets is absorbed by a tolerance of
// 1e-12 of the largest |p_k| on the sign tests, and a cap of 2^m + 16 flips stops a cycle that
// round-off could cause (the last iterate, clipped to μ >= 0, is then returned).
//
// Scenes of bodies have at most kMaxConstraints constraints, and the solver works in fixed arrays.
// A user's model (issue 20: a block on a plane has a contact per node of its bottom edge) may have
// any number: its solver's storage is a ContactLcpWorkspace sized once per run, and its cap on
// flips 64·m + 1024 (least-index pivoting needs about one flip per constraint that joins or leaves
// the active set in a step; the cap only guards against round-off cycles). Neither allocates.
//
// Thread safety: pure functions on caller-owned storage.
#pragma once

#include <array>
#include <vector>

namespace impactid {

inline constexpr int kMaxConstraints = 32;
/// The sign tests' tolerance, relative to the largest |p_k|.
inline constexpr double kContactLcpTolerance = 1e-12;

/// Column-major m×m Delassus matrix and m violations; writes m forces >= 0 to mu. Returns the
/// number of active-set flips it took (0: the penetrating set was the answer). m <=
/// kMaxConstraints.
int solve_contact_lcp(const double* delassus, const double* violation, int m, double* mu);

/// Storage for problems of any size, allocated by resize() (set-up), reused by every solve.
struct ContactLcpWorkspace {
  std::vector<double> factor;  // Cholesky factor of D_SS, m×m
  std::vector<double> rhs;
  std::vector<int> active;
  std::vector<int> in;
  int capacity = 0;

  void resize(int m);
};

/// The same solver for any m <= workspace.capacity, with the same operations (the same bits).
int solve_contact_lcp(const double* delassus, const double* violation, int m, double* mu,
                      ContactLcpWorkspace& workspace);

/// True when D is diagonal with a positive diagonal, exactly (contacts on distinct DOFs of a
/// lumped mass under central difference: the contacts do not interact within a step).
bool is_positive_diagonal(const double* delassus, int m);

/// solve_contact_lcp for a D that is_positive_diagonal, in O(m) instead of a Cholesky factor of
/// the active set per flip: the same bits, since with zero off-diagonals that factorisation
/// reduces exactly to μ_k = (p_k/√d_kk)/√d_kk on the penetrating constraints (p_k/d_kk when
/// there is one), and no flip follows (the penetrating set is the answer). Returns 0 (flips).
int solve_diagonal_contact_lcp(const double* delassus, const double* violation, int m, double* mu);

}  // namespace impactid
