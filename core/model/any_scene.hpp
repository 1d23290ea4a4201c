// The scene of one simulation, whichever of the three kinds it is: the paper's rod
// (core/model/rod_scene.hpp), a scene of bodies (scene.hpp) or a user's model of matrices
// (model_scene.hpp). A simulation holds exactly one; code that differs by kind visits it once
// (std::visit), and the rod's fast paths (its O(1) contact, the batched rod kernels) are chosen
// by the scene being a RodScene, not by a second representation carried alongside it.
//
// Why a closed variant and not a base class: the three kinds have nothing to share at run time
// (a rod is a handful of numbers, a model a pair of sparse matrices), every consumer needs the
// concrete kind anyway, and the compiler then checks that a visit handles each one.
//
// Thread safety: a value.
#pragma once

#include <variant>

#include "core/common/overloaded.hpp"  // for the visits of an AnyScene
#include "core/model/model_scene.hpp"
#include "core/model/rod_scene.hpp"
#include "core/model/scene.hpp"

namespace impactid {

using AnyScene = std::variant<RodScene, Scene, ModelScene>;

}  // namespace impactid
