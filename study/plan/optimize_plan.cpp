#include "study/plan/plan_reader.hpp"

namespace impactid::plan_reading {

namespace {

struct Algorithm {
  const char* name;   ///< as written in a plan
  const char* nlopt;  ///< NLopt's name
};
constexpr std::array<Algorithm, 20> kAlgorithms{{
    {"GN_DIRECT", "GN_DIRECT"},
    {"GN_DIRECT_L", "GN_DIRECT_L"},
    {"GN_ORIG_DIRECT", "GN_ORIG_DIRECT"},
    {"GN_ORIG_DIRECT_L", "GN_ORIG_DIRECT_L"},
    {"GN_CRS2_LM", "GN_CRS2_LM"},
    {"GN_ISRES", "GN_ISRES"},
    {"GN_ESCH", "GN_ESCH"},
    {"LN_COBYLA", "LN_COBYLA"},
    {"LN_BOBYQA", "LN_BOBYQA"},
    {"LN_NELDERMEAD", "LN_NELDERMEAD"},
    {"LN_SBPLX", "LN_SBPLX"},
    {"LN_PRAXIS", "LN_PRAXIS"},
    {"DIRECT", "GN_DIRECT_L"},
    {"CRS2", "GN_CRS2_LM"},
    {"ISRES", "GN_ISRES"},
    {"COBYLA", "LN_COBYLA"},
    {"BOBYQA", "LN_BOBYQA"},
    {"NELDERMEAD", "LN_NELDERMEAD"},
    {"NELDER-MEAD", "LN_NELDERMEAD"},
    {"SBPLX", "LN_SBPLX"},
}};

}  // namespace

void PlanReader::read_optimize(const toml::table& study) {
  OptimizeStudy& out = plan_->optimize;
  const std::vector<std::string> known{"kind",       "algorithm",  "objective", "max_evaluations",
                                       "xtol_rel",   "ftol_rel",   "seed",      "starts",
                                       "parameters", "constraints"};
  const toml::node* parameters = nullptr;
  for (const Entry& e : in_file_order(study)) {
    const std::string key = "study." + e.key;
    const toml::node& node = *e.node;
    if (e.key == "kind") {
    } else if (e.key == "algorithm") {
      const std::string name = string(node, key);
      const auto it = std::find_if(kAlgorithms.begin(), kAlgorithms.end(),
                                   [&](const Algorithm& a) { return name == a.name; });
      if (it == kAlgorithms.end()) {
        std::vector<std::string> names;
        for (const Algorithm& a : kAlgorithms) names.push_back(a.name);
        fail(node, key, "unknown algorithm (algorithms: " + join(names) + ")");
      }
      out.algorithm = it->nlopt;
    } else if (e.key == "objective") {
      out.objective = objective(node, key);
    } else if (e.key == "max_evaluations") {
      const std::int64_t v = integer(node, key);
      if (v < 1 || v > std::numeric_limits<int>::max()) {
        fail(node, key, "must lie in [1, " + std::to_string(std::numeric_limits<int>::max()) + "]");
      }
      out.max_evaluations = static_cast<long>(v);
    } else if (e.key == "xtol_rel" || e.key == "ftol_rel") {
      const double v = number(node, key);
      if (!(v >= 0.0)) fail(node, key, "must be >= 0");
      (e.key == "xtol_rel" ? out.xtol_rel : out.ftol_rel) = v;
    } else if (e.key == "seed") {
      const std::int64_t v = integer(node, key);
      if (v < 0 || v > std::numeric_limits<unsigned>::max()) {
        fail(node, key,
             "must lie in [0, " + std::to_string(std::numeric_limits<unsigned>::max()) + "]");
      }
      out.seed = static_cast<unsigned>(v);
    } else if (e.key == "starts") {
      const std::int64_t v = integer(node, key);
      if (v < 1 || v > kMaxOptimizeStarts) {
        fail(node, key, "must lie in [1, " + std::to_string(kMaxOptimizeStarts) + "]");
      }
      out.starts = static_cast<long>(v);
    } else if (e.key == "parameters") {
      parameters = &node;
    } else if (e.key == "constraints") {
      out.constraints =
          constraints(table(node, key, "must be a table of indicator = { max, min }"));
    } else if (e.key == "practical") {
      fail(node, key,
           "is for grid and list studies; an optimisation states its limits as "
           "[study.constraints]");
    } else {
      fail_unknown(node, key, "optimize keys", known);
    }
  }
  if (!parameters) {
    fail_missing(study, "study.parameters",
                 "an optimize study needs a table [study.parameters] of name = { from, to }");
  }
  const toml::table& table_ =
      table(*parameters, "study.parameters", "must be a table of name = { from, to, start }");
  for (const Entry& e : in_file_order(table_)) {
    const std::string key = "study.parameters." + e.key;
    const ParameterInfo& info = varied_parameter(e, key, "an optimisation parameter");
    if (info.kind == ParameterKind::integer) {
      fail(*e.node, key,
           "is an integer parameter: NLopt varies parameters continuously; vary it "
           "in a grid or list study");
    }
    const toml::table& p = table(*e.node, key, "must be { from = .., to = .., start = .. }");
    const toml::node *from = nullptr, *to = nullptr, *start = nullptr;
    for (const Entry& f : in_file_order(p)) {
      if (f.key == "from") {
        from = f.node;
      } else if (f.key == "to") {
        to = f.node;
      } else if (f.key == "start") {
        start = f.node;
      } else {
        fail_unknown(*f.node, key + "." + f.key, "parameter keys", {"from", "to", "start"});
      }
    }
    if (!from) fail_missing(p, key + ".from", "a parameter needs bounds from and to");
    if (!to) fail_missing(p, key + ".to", "a parameter needs bounds from and to");
    OptimizeParameter parameter{e.key, number(*from, key + ".from"), number(*to, key + ".to"),
                                std::nullopt};
    if (!(parameter.lower < parameter.upper)) fail(*to, key + ".to", "must be > from");
    if (start) {
      const double s = number(*start, key + ".start");
      if (!(s >= parameter.lower && s <= parameter.upper)) {
        fail(*start, key + ".start", "must lie in [from, to]");
      }
      parameter.start = s;
    }
    parameter_nodes_[e.key] = {e.node, from, to, start};
    out.parameters.push_back(parameter);
  }
  if (out.parameters.empty()) {
    fail(*parameters, "study.parameters", "must name at least one parameter");
  }
}

std::vector<std::pair<std::string, double>> PlanReader::objective(const toml::node& node,
                                                                  const std::string& key) const {
  const auto check = [&](const toml::node& where, const std::string& where_key,
                         const std::string& name) {
    if (!find_indicator(name)) {
      fail(where, where_key, "unknown indicator (indicators: " + join(indicator_names()) + ")");
    }
  };
  if (const auto* s = node.as_string()) {
    check(node, key, s->get());
    return {{s->get(), 1.0}};
  }
  const auto* t = node.as_table();
  if (!t) fail(node, key, "must be an indicator name or a table of indicator = weight");
  std::vector<std::pair<std::string, double>> out;
  for (const Entry& e : in_file_order(*t)) {
    const std::string weight_key = key + "." + e.key;
    check(*e.node, weight_key, e.key);
    const double w = number(*e.node, weight_key);
    if (w == 0.0) fail(*e.node, weight_key, "must not be 0 (leave the indicator out)");
    out.emplace_back(e.key, w);
  }
  if (out.empty()) fail(node, key, "must name at least one indicator");
  return out;
}

void PlanReader::check_optimize() const {
  const auto& parameters = plan_->optimize.parameters;
  std::vector<double> start;
  for (const OptimizeParameter& p : parameters) {
    start.push_back(p.initial());
  }
  enum class Where { start, lower, upper };
  const auto check = [&](std::size_t moved, Where where) {
    std::vector<double> x = start;
    if (where == Where::lower) x[moved] = parameters[moved].lower;
    if (where == Where::upper) x[moved] = parameters[moved].upper;
    std::vector<std::string> names;
    for (const OptimizeParameter& p : parameters) names.push_back(p.name);
    const std::string suffix = where == Where::start
                                   ? " (at the start point: " + values_text(names, x) + ")"
                                   : " (with " + parameters[moved].name + " at its " +
                                         (where == Where::lower ? "lower" : "upper") +
                                         " bound: " + values_text(names, x) + ")";

    SimulationSettings settings = plan_->base;
    std::optional<ParameterError> error;
    for (std::size_t k = 0; k < parameters.size() && !error; ++k) {
      error = assign(settings, parameters[k].name, x[k]);
    }
    if (!error) {
      auto built = build(settings);
      if (auto* e = std::get_if<ParameterError>(&built)) error = *e;
    }
    if (!error) return;
    const auto found = parameter_nodes_.find(error->field);
    if (found == parameter_nodes_.end()) fail_base(*error, suffix);
    const ParameterNodes& nodes = found->second;
    const std::string key = "study.parameters." + error->field;
    const bool is_moved = error->field == parameters[moved].name;
    if (is_moved && where == Where::lower) {
      fail(*nodes.from, key + ".from", error->constraint + suffix);
    }
    if (is_moved && where == Where::upper) {
      fail(*nodes.to, key + ".to", error->constraint + suffix);
    }
    if (nodes.start) fail(*nodes.start, key + ".start", error->constraint + suffix);
    fail(*nodes.table, key, error->constraint + suffix);
  };
  check(0, Where::start);
  for (std::size_t k = 0; k < parameters.size(); ++k) {
    check(k, Where::lower);
    check(k, Where::upper);
  }
}

}  // namespace impactid::plan_reading
