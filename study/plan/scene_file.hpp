// Scenes of bodies written in TOML (issue 18), in a plan's [scene] table or in a scene file of
// their own (`impactid simulate --scene FILE.toml`, whose keys are those of [scene], at the root
// or under [scene]; a plan file is a scene file too, its study ignored):
//
//   [[scene.body]]                 # left to right
//   name = "striker"               # letters, digits, '_'; default body1, body2, ...
//   velocity = 1000.0              # mm/s, +x; default 0
//   [[scene.body.segment]]         # left to right; default one segment of the paper's rod
//   length = 10.0                  # mm;   default 20
//   elements = 100                 #       default 200
//   youngs_modulus = 90.0          # MPa;  default 90
//   density = 7.85e-9              # t/mm³; default 7.85e-9
//   area = 1.0                     # mm²;  default 1
//
//   [[scene.body]]
//   name = "bar"
//   gap = 0.01                     # mm, to the body (or wall) on the left; default 0
//   displacement = [0.0, 0.0]      # mm: initial u at its first and last node, linear in
//                                  # between (an initial strain); default none
//   length = 60.0                  # a body of one segment may give its keys itself
//   elements = 600
//
//   [scene.wall.right]             # optional walls; their presence is the wall
//   kind = "contact"               # "contact" (default): a rigid obstacle at `gap`;
//                                  # "clamped": the end node held at u = 0 (no gap, no contact)
//   gap = 0.05                     # mm; default 0
//
// The first body's `gap` is its gap to the left wall (wall.left.gap says the same; give one).
// Gaps count from the undisplaced ends: an initial displacement must keep every contact open or
// just closed, and be 0 at a clamped end (core/model/scene.hpp says what such a scene turns off).
// `primary_contact = "striker-bar"` chooses the contact whose indicators a sweep stores;
// `gravity = -9810.0` (mm/s², along x; default 0) accelerates every body toward the wall it
// points to (negative: the left one), which must exist (core/model/scene.hpp: Scene::gravity). The
// whole-scene keys (mass, rayleigh_mass, rayleigh_stiffness, courant, dt, t_end) are the
// ordinary [scene] parameters; the one-body keys (length, elements, …, gap, far_gap) belong to
// bodies and segments here and are refused at the [scene] level.
#pragma once

#include <toml++/toml.h>

#include <string>

#include "core/model/scene.hpp"
#include "study/plan/table_fail.hpp"

namespace impactid {

/// Whether a [scene] table describes a scene of bodies (it has `body` or `wall`).
bool is_scene_of_bodies(const toml::table& scene);

/// Whether `key` of a [scene] table belongs to the bodies' description (body, wall,
/// primary_contact, gravity) rather than to the whole-scene parameters.
bool is_scene_of_bodies_key(const std::string& key);

/// Reads the bodies, walls, primary contact and gravity of a [scene] table; `prefix` is the table's
/// dotted key for messages ("scene"). Keys it does not own are left to the caller. Range checks
/// are validate()'s; this checks structure and types. `fail` must throw.
Scene read_scene_of_bodies(const toml::table& scene, const std::string& prefix,
                           const TableFail& fail);

}  // namespace impactid
