// The named parameters of one simulation, as users write them: the single table behind the
// command line (`--youngs-modulus`), plan files (`youngs_modulus = 90.0`) and sweep axes.
// Names are snake_case; the command line uses them with '-' for '_'.
//
// Settings are flat and record what was given, so that rules across parameters (Newmark's δ
// or β and γ; courant or dt; a parameter the method does not take) are checked in one place,
// build(), and reported with the parameter's name.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

#include "core/common/parameter_error.hpp"
#include "core/methods/method.hpp"
#include "core/methods/method_registry.hpp"
#include "core/model/any_scene.hpp"
#include "core/model/model_scene.hpp"
#include "core/model/rod_scene.hpp"
#include "core/model/scene.hpp"
#include "core/run/simulation.hpp"
#include "metrics/indicators.hpp"
#include "metrics/verdict.hpp"
#include "study/plan/parameter_value.hpp"

namespace impactid {

/// How a converged reference is computed (a scene of bodies with damping, a user's model; the
/// rod's reference is exact). Unset fields take the scene kind's defaults
/// (core/reference/scene_reference.hpp, core/reference/model_reference.hpp); the tolerance is
/// IndicatorOptions::reference_tolerance.
struct ReferenceSettings {
  std::optional<MethodKind> method;  ///< at its default parameters
  std::optional<int> max_refinements;
};

/// Method parameters as given; unset ones take the method's defaults in build()
/// (core/methods/method_registry.hpp: which method takes which key).
struct MethodSettings {
  MethodKind kind = MethodKind::hht;
  MethodArguments given;
};

struct SimulationSettings {
  RodScene scene;
  bool courant_given = false;
  /// A scene of bodies ([[scene.body]] in a plan or a scene file). When set it is the scene: the
  /// whole-scene keys of `scene` (mass, rayleigh_*, courant, dt, t_end) apply to it, and the
  /// one-body keys (length, elements, …, gap, far_gap) may not be given (rod_keys).
  std::optional<Scene> bodies;
  /// One-body keys given (by assign()) with their values, to refuse them beside a scene of
  /// bodies.
  std::vector<std::pair<std::string, double>> rod_keys;
  /// A user's model ([scene] kind = "matrices", study/plan/model_file.hpp). When set it is the
  /// scene: dt, t_end and the Rayleigh factors of `scene` apply to it; the rod's other keys may not
  /// be given.
  std::optional<ModelScene> model;
  bool reference_tolerance_given = false;
  MethodSettings method;
  IndicatorOptions indicators;
  RunOptions run;
  ReferenceSettings reference;
  VerdictThresholds verdict;  ///< verdict_eps_p, verdict_nop_p, verdict_eps_v, verdict_nop_v
};

/// A complete, validated simulation.
struct Simulation {
  /// The scene that runs, valid and complete: the rod, a scene of bodies (its mass, step and end
  /// time set from the settings) or a user's model.
  AnyScene scene;
  MethodParams method;
  IndicatorOptions indicators;
  RunOptions run;
  ReferenceSettings reference;
  VerdictThresholds verdict;  ///< how evaluate() judges the run (metrics/verdict.hpp)

  /// The scene when it is of that kind, else null.
  const RodScene* rod() const { return std::get_if<RodScene>(&scene); }
  const Scene* bodies() const { return std::get_if<Scene>(&scene); }
  const ModelScene* model() const { return std::get_if<ModelScene>(&scene); }
  RodScene* rod() { return std::get_if<RodScene>(&scene); }
  Scene* bodies() { return std::get_if<Scene>(&scene); }
  ModelScene* model() { return std::get_if<ModelScene>(&scene); }
};

enum class ParameterGroup { scene, method, output };
enum class ParameterKind { real, integer, choice };

struct ParameterInfo {
  const char* name;  ///< snake_case key
  ParameterGroup group;
  ParameterKind kind;
  const char* unit;         ///< "" when dimensionless
  const char* description;  ///< one line, with the default and range
  const char* choices;      ///< "lumped|consistent" for choice parameters, else ""
  const char* methods;      ///< methods that take it ("newmark|hht"), "" = every method
};

/// Every parameter, in the order --help lists them.
std::span<const ParameterInfo> parameter_table();
const ParameterInfo* find_parameter(std::string_view name);

/// Sets one parameter. Errors: unknown name, wrong kind, non-integral integer, unknown choice,
/// courant together with dt. Range checks happen in build(). Keys of a scene of bodies are
/// dotted paths (scene_path.hpp): `body.striker.velocity`, `body.bar.segment.1.area`,
/// `wall.right.gap`, `primary_contact`; they need settings.bodies.
std::optional<ParameterError> assign(SimulationSettings& settings, std::string_view name,
                                     const ParameterValue& value);
/// The same from text (the command line): numbers are parsed strictly.
std::optional<ParameterError> assign_text(SimulationSettings& settings, std::string_view name,
                                          std::string_view text);

/// The numeric value a parameter has in a built simulation, derived values included (δ of HHT
/// when only α was given, β and γ of every Newmark-family method); nothing for a choice
/// parameter or one the method does not have.
std::optional<double> numeric_value(const Simulation& simulation, std::string_view name);

/// The value of the `mass` key in a built simulation: the rod's or the scene of bodies' choice; a
/// model's M is its file, and the key keeps its default (lumped), which build() requires of it.
MassMatrix mass_key(const Simulation& simulation);

/// A method's numbers as reports print them: " (delta = 0.3, alpha = -0.3, beta = 0.4225,
/// gamma = 0.8)", every parameter and derived coefficient (%.6g); "" for a method without.
std::string method_values_text(const MethodParams& method);

/// The options of the simulation's converged reference: the scene kind's defaults with what the
/// settings give (reference_tolerance, reference_method, reference_max_refinements).
ReferenceOptions reference_options(const Simulation& simulation);

/// Checks every rule and range and builds the simulation, or names the first bad parameter.
std::variant<Simulation, ParameterError> build(const SimulationSettings& settings);

}  // namespace impactid
