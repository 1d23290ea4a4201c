// Plan files: what users launch. A TOML file (toml++ 3.3) with sections [scene], [method],
// [study] and [output]; every key is documented in plans/README.md. A study is a grid, a list
// or an optimisation of simulations, or a spectral study of the integrators themselves (no
// simulation: amplification-matrix curves, core/spectral/amplification.hpp).
//
// load_plan() checks everything before anything runs — unknown keys, wrong types, values out
// of range, parameters the method does not take, and every point of a grid or list — and
// throws PlanError as "file:line:column: key = value: what is wrong". The key is the dotted
// path (`study.axes.delta`, `study.points[2].delta`), the value is as written in the file (for
// a grid point: the point's value, with the point named after the message), and line:column is
// where that value starts (toml++ counts columns in characters). The parameter names, kinds
// and ranges all come from the settings table and build() (simulation_settings.hpp): this
// module knows the plan's structure, not the parameters. A work-precision study times every
// method of a list over a set of meshes and Courant numbers (study/studies/work_precision.hpp).
#pragma once

#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "study/plan/axis_expression.hpp"
#include "study/plan/simulation_settings.hpp"

namespace impactid {

struct PlanError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

enum class StudyKind { grid, list, optimize, spectral, work_precision };
const char* to_string(StudyKind kind);

/// An independent grid axis: `delta = { from = 0.0, to = 1.0, partitions = 40 }` (k partitions
/// give k+1 evenly spaced values from + i*(to-from)/k, as in Dakota, the last exactly `to`) or
/// `courant = { values = [0.25, 0.5, 1.0] }`. A choice parameter is an axis of its words,
/// `contact = { values = ["lagrange", "penalty"] }`: its values are then the words' positions
/// 0, 1, … and `labels` the words, in the order written.
struct GridAxis {
  std::string name;  ///< a parameter of the settings table
  std::vector<double> values;
  std::vector<std::string> labels;  ///< a choice axis: its words; empty for a numeric axis
};

/// A coupled axis: `delta = "-1.5*alpha"`, evaluated at every point from the independent axes;
/// a line through the grid rather than a dimension of it (the paper's eq. 19).
struct CoupledAxis {
  std::string name;
  AxisExpression expression;
};

/// One point of a `list` study: parameter name -> value, applied over [scene] and [method].
using ListPoint = std::vector<std::pair<std::string, ParameterValue>>;

struct OptimizeParameter {
  std::string name;             ///< a real (not integer) parameter the method takes
  double lower, upper;          ///< bounds, lower < upper
  std::optional<double> start;  ///< default: the middle of the bounds
  double initial() const { return start.value_or(0.5 * (lower + upper)); }
};

/// indicator <= max and/or indicator >= min. Also the thresholds of a practical range
/// ([study.practical] of a grid or list, study/studies/practical_range.hpp).
struct IndicatorConstraint {
  std::string indicator;
  std::optional<double> min, max;
};

/// One method of a spectral or work-precision study, `{ method = "hht", alpha = -0.3 }` in the
/// plan.
struct SpectralMethod {
  MethodParams params;  ///< built and validated by build() (simulation_settings.hpp)
  /// "hht alpha=-0.3": the method name, then the keys as given, in file order (numbers in
  /// their shortest round-trip form). Unique within a study.
  std::string label;
  /// The keys as given, unset ones left to the method's defaults: a work-precision study applies
  /// them over [scene] at each point (`params` above was built on the default scene).
  MethodSettings settings;
};

/// `kind = "spectral"`: the spectral properties of the integrators on ü + ω²u = 0
/// (core/spectral/amplification.hpp), written by study/studies/spectral_study.hpp; no simulation
/// runs.
struct SpectralStudy {
  std::vector<double> omega_dt;         ///< Ω = ω·Δt, each > 0 and finite, no value twice
  std::vector<SpectralMethod> methods;  ///< at least one
  /// HHT α for δ_min(α) and the stability map, each in [−0.5, 0]; default −0.5 … 0 in 20
  /// partitions (the grid of plans/hht-delta-alpha.toml).
  std::vector<double> alpha;
  /// HHT δ of the stability map, each >= 0; default 0 … 1 in 40 partitions.
  std::vector<double> delta;
  double omega_dt_reference = 1.0;   ///< finite Ω of δ_min (besides Ω → 0), > 0
  double stability_omega_max = 1e4;  ///< upper end of the stability scan (is_stable), > 0
};

/// `kind = "work-precision"`: every method on every (elements, courant) pair of the [scene]
/// rod, each run timed `repeats` times (study/studies/work_precision.hpp). Points are ordered
/// (method, elements, courant), the last fastest.
struct WorkPrecisionStudy {
  /// Default: the five methods at the parameters this project recommends (docs/methods.md): cdm,
  /// backward-euler, newmark δ = 0.3, hht α = −0.3 δ = 0.45 (eq. 19), generalized-alpha ρ∞ = 0.8.
  std::vector<SpectralMethod> methods;
  /// Element counts n (>= 1, no value twice), in plan order; default 50, 100, 200, 400, 800.
  std::vector<long> elements;
  /// Courant numbers c·Δt/h (> 0, finite, no value twice), in plan order; default 0.25, 0.5, 1,
  /// 2, 4 (central difference is unstable above 1: those runs are kept, with their status).
  std::vector<double> courant;
  /// Runs per point; the stored wall time is their minimum (>= 1, <= 100, default 5).
  int repeats = 5;
};

/// The most independent searches an optimize study may ask for (`starts`).
inline constexpr long kMaxOptimizeStarts = 100000;

struct OptimizeStudy {
  /// NLopt's full name, always: GN_DIRECT, GN_DIRECT_L, GN_ORIG_DIRECT, GN_ORIG_DIRECT_L,
  /// GN_CRS2_LM, GN_ISRES, GN_ESCH, LN_COBYLA, LN_BOBYQA, LN_NELDERMEAD, LN_SBPLX or LN_PRAXIS.
  /// Plans may also use the short names DIRECT (GN_DIRECT_L), CRS2 (GN_CRS2_LM), ISRES,
  /// COBYLA, BOBYQA, NELDERMEAD or NELDER-MEAD, SBPLX; the full name is stored.
  std::string algorithm = "LN_COBYLA";
  /// Minimised: sum of weight × indicator (e.g. {eps_p: 1}).
  std::vector<std::pair<std::string, double>> objective{{"eps_p", 1.0}};
  std::vector<OptimizeParameter> parameters;
  std::vector<IndicatorConstraint> constraints;
  long max_evaluations = 200;
  double xtol_rel = 1e-4;
  double ftol_rel = 0.0;  ///< 0: not used
  unsigned seed = 1;      ///< for the stochastic algorithms (CRS2, ISRES): results repeat
  /// Independent searches (multi-start, study/studies/optimizer.hpp): search 0 from the
  /// parameters' `start`, search k >= 1 from the k-th point of a Halton sequence in the bounds
  /// and with seed + k. Each has its own max_evaluations; they run in parallel.
  long starts = 1;
};

struct OutputSpec {
  std::filesystem::path file;           ///< default results/<plan name>.h5
  std::vector<std::string> indicators;  ///< default: every indicator of indicator_table()
  double checkpoint_seconds = 10.0;     ///< how often a long run is saved, > 0
  /// When set (grid and list studies), the time histories of every point are written to
  /// <histories>/point-<flat index>.h5 in the layout of `impactid simulate --history`.
  std::optional<std::filesystem::path> histories;
};

struct Plan {
  std::filesystem::path path;
  std::string name;         ///< `name` key, default the file stem
  std::string description;  ///< `description` key, default ""
  std::string text;         ///< the whole file, stored in results
  SimulationSettings base;  ///< [scene] and [method]
  StudyKind kind = StudyKind::grid;
  std::vector<GridAxis> axes;  ///< grid: in file order; the last varies fastest
  std::vector<CoupledAxis> coupled;
  std::vector<ListPoint> points;  ///< list
  /// grid and list: [study.practical], the thresholds that make a point practical (status ok
  /// and every indicator within its bounds); empty when the plan has none.
  std::vector<IndicatorConstraint> practical;
  OptimizeStudy optimize;             ///< optimize
  SpectralStudy spectral;             ///< spectral
  WorkPrecisionStudy work_precision;  ///< work-precision
  OutputSpec output;
};

/// Reads and checks a scene file (study/plan/scene_file.hpp): its scene as the settings a plan's
/// [scene] gives, checked by build() with the default method. Throws PlanError, as load_plan.
SimulationSettings load_scene_file(const std::filesystem::path& path);
/// The same from text; `source` names it in messages and is the folder a model's files are
/// relative to.
SimulationSettings parse_scene_file(const std::string& text, const std::filesystem::path& source);

/// Reads and checks a plan file. Throws PlanError.
Plan load_plan(const std::filesystem::path& path);
/// The same from text; `source` names it in messages and gives the default name.
Plan parse_plan(const std::string& text, const std::filesystem::path& source);

}  // namespace impactid
