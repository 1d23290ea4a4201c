// The keys of a scene of bodies as dotted paths, the names a sweep axis, an optimisation
// parameter or the command line gives them (issue 18):
//   body.<body>.velocity, body.<body>.gap,
//   body.<body>.displacement.left, body.<body>.displacement.right (the initial displacement at
//     the body's first and last node, Body::displacement),
//   body.<body>.segment.<k>.{length, elements, youngs_modulus, density, area},
//   wall.left.gap, wall.right.gap, primary_contact, gravity (Scene::gravity, mm/s² along x),
// where <body> is a body's name or its position (1 = the leftmost) and <k> counts a body's
// segments from 1 (the leftmost). A body's gap is to its left neighbour; the first body's gap is
// the left wall's (wall.left.gap), as in a scene file. A wall's kind (contact or clamped) is the
// scene file's alone: its path, wall.<side>.kind, is refused with that reason.
#pragma once

#include <optional>
#include <string_view>

#include "core/common/parameter_error.hpp"
#include "core/model/scene.hpp"
#include "study/plan/parameter_value.hpp"

namespace impactid {

/// Whether `name` is a dotted scene path (it need not name an existing body).
bool is_scene_path(std::string_view name);

/// Sets the value at `path`: numbers for every key but primary_contact (a string); elements must
/// be an integer. Errors name the path: an unknown key, body, segment or wall, a wrong kind.
/// Range checks are validate()'s.
std::optional<ParameterError> assign_scene_path(Scene& scene, std::string_view path,
                                                const ParameterValue& value);

/// The unit of the number at `path` in the results files' spelling ("mm", "mm/s", "1", …).
const char* scene_path_units(std::string_view path);

/// The numeric value at `path`, or nothing if the path names nothing numeric in the scene.
std::optional<double> scene_path_value(const Scene& scene, std::string_view path);

}  // namespace impactid
