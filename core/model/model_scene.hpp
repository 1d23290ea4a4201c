// A user's own model as a scene (issue 20): the semi-discrete equations of a finite element model
// made elsewhere (M, K and optionally C, as Matrix Market files: study/plan/model_file.hpp reads
// them), its initial state, and its unilateral contacts, each on one DOF (a rigid wall) or between
// two (node to node):
//   wall, side "upper":  u[dof] <= gap           force −λ on dof
//   wall, side "lower":  u[dof] >= −gap          force +λ on dof
//   pair [i, j]:         u[i] − u[j] <= gap      force −λ on i, +λ on j
// with λ >= 0 the contact force in the model's units; a contact's pressure is λ/area and its
// velocity that of its velocity DOF. DOFs count from 0 (a Matrix Market file's row minus one).
// Units are the user's: they are text for the reports.
//
// The run (core/run/simulation.hpp) sees the model as an AssembledScene like every other scene:
// - when M, C and K are all tridiagonal (a 1D chain, the paper's rod exported by `impactid
//   export-model`) as a SecondOrderSystem, on the integrators and kernels of the built-in scenes;
//   with a single upper wall, through the named contact of the paper's scene, so that the exported
//   rod runs the built-in rod's operations, bit for bit;
// - otherwise as a SparseSystem (core/model/sparse_system.hpp), on the sparse integrators.
// Before the first contact a model flies rigidly when nothing deforms or damps it: u(0) = 0 and
// K·v0 = C·v0 = 0 exactly (a uniform velocity of a free body). Its free flight is then filled in
// up to the earliest time a gap closes, as for the built-in scenes.
//
// Thread safety: values; the model is shared read-only between copies of a scene.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/common/parameter_error.hpp"
#include "core/common/run_record.hpp"
#include "core/model/scene_assembly.hpp"
#include "core/model/sparse_system.hpp"

namespace impactid {

struct ModelContact {
  std::string name;
  Eigen::Index plus = -1;  ///< u[plus] − u[minus] <= gap; −1: the term is absent
  Eigen::Index minus = -1;
  double gap = 0.0;               ///< >= 0, in the model's length unit
  double area = 1.0;              ///< pressure = λ/area; > 0 (1: the pressure is the force)
  Eigen::Index velocity_dof = 0;  ///< the DOF whose velocity the contact reports

  bool operator==(const ModelContact&) const = default;
};

/// A history the user supplies to measure runs against: samples at times t of some contacts.
struct ReferenceHistory {
  std::string source;                    ///< the file, for reports
  std::vector<double> t;                 ///< increasing
  std::vector<ContactSamples> contacts;  ///< Model::contacts order; empty vectors: not given
};

/// A loaded model: what the files said, checked (study/plan/model_file.hpp).
struct Model {
  SparseMatrix mass, stiffness, damping;  ///< damping 0×0 when absent
  Eigen::VectorXd initial_displacement;   ///< size n (zero when not given)
  Eigen::VectorXd initial_velocity;       ///< size n
  /// A constant load ([scene.load]: f per DOF and its potential at u = 0, core/model/
  /// constant_load.hpp); empty force: none.
  ConstantLoad load;
  std::vector<ModelContact> contacts;  ///< at least one
  std::string units;                   ///< as the scene states them, for reports
  std::string source;                  ///< the files it was read from, for reports
  double omega_bound = 0.0;  ///< gershgorin_omega(mass, stiffness), set when the model is read
  std::optional<ReferenceHistory> reference;  ///< a supplied reference, if any

  Eigen::Index size() const { return mass.rows(); }
};

/// An upper bound of the model's highest angular frequency ω_max [rad per time unit]: Gershgorin's
/// bound on M_L⁻¹·K, ω² <= max_i Σ_j |K_ij| / m_i, with m_i the row sums of M (M itself when it is
/// diagonal). A model's Courant number is Δt·ω/2 with this ω: central difference with that lumped
/// mass is stable below 1, and for the paper's rod (lumped) it is the rod's c·Δt/h, since ω = 2c/h
/// there. O(nnz); computed when the model is read (Model::omega_bound).
double gershgorin_omega(const SparseMatrix& mass, const SparseMatrix& stiffness);

/// The units a model's reports give its quantities, from its `units` text when that names the
/// force, length, time and mass units in this order, comma-separated ("N, mm, s, t", as the shipped
/// models and `impactid export-model` write it): pressure force/length^2, velocity length/time,
/// displacement length, energy force*length, time time. All empty for any other text, which stays
/// a free description.
struct ModelUnits {
  std::string force, length, time, mass;
  std::string pressure() const { return force.empty() ? "" : force + "/" + length + "^2"; }
  std::string velocity() const { return length.empty() ? "" : length + "/" + time; }
  std::string energy() const { return force.empty() ? "" : force + "*" + length; }
};
ModelUnits model_units(const std::string& text);

struct ModelScene {
  std::shared_ptr<const Model> model;
  double dt = 0.0;     ///< > 0, in the model's time unit
  double t_end = 0.0;  ///< > dt
  /// Rayleigh damping added to the model's C: a0·M + a1·K (>= 0 each).
  double rayleigh_mass = 0.0;
  double rayleigh_stiffness = 0.0;
  /// The contact whose indicators a sweep stores; default the first listed.
  std::optional<std::string> primary_contact;

  /// The same model object and the same parameters.
  bool operator==(const ModelScene& other) const;
};

/// First invalid field (dt, t_end, rayleigh_*, primary_contact), or nothing.
std::optional<ParameterError> validate(const ModelScene& scene);

/// Index of the primary contact in model->contacts; the scene must be valid.
int primary_contact_index(const ModelScene& scene);

/// The scene must be valid.
AssembledScene assemble(const ModelScene& scene);

}  // namespace impactid
