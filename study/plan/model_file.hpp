// A user's model in a scene file or a plan's [scene] table (issue 20), `kind = "matrices"`:
//
//   [scene]
//   kind = "matrices"
//   units = "N, mm, s, t"          # text for the reports; default ""
//   dt = 4.23e-8                   # the step and the end time, in the model's time unit (sweep
//   t_end = 6.13e-6                #   axes like every scene parameter); both required
//   primary_contact = "bottom_20"  # whose indicators a sweep stores; default the first contact
//   rayleigh_mass = 0.0            # optional: a0·M + a1·K added to the model's C
//   rayleigh_stiffness = 0.0
//
//   [scene.matrices]               # Matrix Market files, paths relative to this file
//   mass = "M.mtx"                 # symmetric positive definite (diagonal for central difference)
//   stiffness = "K.mtx"            # symmetric positive semi-definite
//   damping = "C.mtx"              # optional, symmetric
//
//   [scene.dof_sets]               # optional named sets of DOFs: a list of DOFs, "all", or a
//   all_y = "1::2"                 #   Python slice "start:stop:step" over 0..n-1
//
//   [scene.initial]                # optional; default zero
//   displacement = "u0.mtx"        # a Matrix Market vector, or
//   velocity = { value = -1000.0, dofs = "all_y" }   # a value over a set (a name, list, slice)
//
//   [[scene.contact]]              # at least one
//   name = "bottom_0"              # unique; letters, digits, '_', '-'
//   dof = 1                        # a wall: side "upper" (u <= gap, default) or "lower" (u >=
//   −gap) side = "lower" # dofs = [3, 7]                # or a pair: u[3] − u[7] <= gap gap = 0.001
//   # >= 0; default 0 area = 0.25                    # pressure = λ/area; default 1 velocity_dof =
//   1               # default: dof, or the first of the pair
//
//   [scene.reference]              # optional: the history the runs are measured against
//   file = "reference.csv"         #   columns t, <contact>.pressure, <contact>.velocity;
//                                  #   or .h5/.hdf5: datasets t and <contact>.pressure, … (or
//                                  #   pressure.<contact>, …, as `simulate --history` writes)
//
// DOFs count from 0 (a Matrix Market row minus one). Without [scene.reference] the runs are
// measured against a converged solution (core/model_reference.hpp).
//
// Every error names the file, the line and the value: a matrix that is not square, sizes that
// disagree, an entry that is not a number (the Matrix Market reader's), a matrix that is not
// symmetric, M not positive definite (the pivot and its DOF), a DOF out of range, a DOF with two
// wall contacts (their constraint rows would be dependent, the contact problem singular), a
// reference that does not cover the run. Large files are read with a progress line.
#pragma once

#include <toml++/toml.h>

#include <filesystem>
#include <string>

#include "core/model_scene.hpp"
#include "study/plan/scene_file.hpp"

namespace impactid {

/// Whether a [scene] table describes a model (kind = "matrices").
bool is_model_scene(const toml::table& scene);
/// Whether `key` of a [scene] table belongs to the model's description rather than to the
/// whole-scene parameters (dt, t_end, rayleigh_*).
bool is_model_scene_key(const std::string& key);

/// Reads and checks the model of a [scene] table; `prefix` is the table's dotted key
/// ("scene"), `directory` the folder its paths are relative to. `fail` must throw. dt, t_end and
/// the Rayleigh factors are left to the caller (they are sweepable parameters).
ModelScene read_model_scene(const toml::table& scene, const std::string& prefix,
                            const std::filesystem::path& directory, const SceneTableFail& fail);

}  // namespace impactid
