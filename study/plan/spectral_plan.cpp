#include "study/plan/plan_reader.hpp"

namespace impactid::plan_reading {

void PlanReader::read_spectral(const toml::table& study) {
  SpectralStudy& out = plan_->spectral;
  const std::vector<std::string> known{
      "kind", "omega_dt", "methods", "alpha", "delta", "omega_dt_reference", "stability_omega_max"};
  const toml::node *omega_dt = nullptr, *methods = nullptr, *alpha = nullptr, *delta = nullptr;
  for (const Entry& e : in_file_order(study)) {
    const std::string key = "study." + e.key;
    const toml::node& node = *e.node;
    if (e.key == "kind") {
    } else if (e.key == "omega_dt") {
      omega_dt = &node;
      out.omega_dt = log_axis_values(node, key);
    } else if (e.key == "methods") {
      methods = &node;
      out.methods = spectral_methods(node, key);
    } else if (e.key == "alpha" || e.key == "delta") {
      (e.key == "alpha" ? alpha : delta) = &node;
      const toml::table& axis =
          table(node, key, "must be { from = .., to = .., partitions = .. } or { values = [..] }");
      std::vector<double> values = axis_values(axis, key);
      for (const double v : values) {
        // The same rule as the method's own (validate), so the map holds no invalid HHT.
        HhtParams hht{.alpha = e.key == "alpha" ? v : -0.5, .delta = 0.5};
        if (e.key == "delta") hht.delta = v;
        if (const auto error = validate(MethodParams{hht})) {
          fail(node, key,
               "holds " + e.key + " = " + format_value(v) + ", which " + error->constraint);
        }
      }
      (e.key == "alpha" ? out.alpha : out.delta) = std::move(values);
    } else if (e.key == "omega_dt_reference" || e.key == "stability_omega_max") {
      const double v = number(node, key);
      if (!(v > 0.0)) fail(node, key, "must be > 0");
      (e.key == "omega_dt_reference" ? out.omega_dt_reference : out.stability_omega_max) = v;
    } else if (e.key == "practical") {
      fail(node, key, "is for grid and list studies (a spectral study has no indicators)");
    } else {
      fail_unknown(node, key, "spectral keys", known);
    }
  }
  if (!omega_dt) {
    fail_missing(study, "study.omega_dt",
                 "a spectral study needs omega_dt = { from = .., to = .., points = .. } "
                 "(log-spaced) or { values = [..] }");
  }
  if (!methods) {
    fail_missing(study, "study.methods",
                 "a spectral study needs methods = [{ method = \"..\", .. }, ..]");
  }
  const auto linear = [](double from, double to, int partitions) {
    std::vector<double> v(static_cast<std::size_t>(partitions) + 1);
    for (int i = 0; i < partitions; ++i) v[i] = from + i * (to - from) / partitions;
    v.back() = to;
    return v;
  };
  if (!alpha) out.alpha = linear(-0.5, 0.0, 20);
  if (!delta) out.delta = linear(0.0, 1.0, 40);
}

std::vector<double> PlanReader::log_axis_values(const toml::node& node,
                                                const std::string& key) const {
  const toml::table& axis = table(
      node, key, "must be { from = .., to = .., points = .. } (log-spaced) or { values = [..] }");
  const toml::node *from = nullptr, *to = nullptr, *points = nullptr, *values = nullptr;
  for (const Entry& e : in_file_order(axis)) {
    if (e.key == "from") {
      from = e.node;
    } else if (e.key == "to") {
      to = e.node;
    } else if (e.key == "points") {
      points = e.node;
    } else if (e.key == "values") {
      values = e.node;
    } else {
      fail_unknown(*e.node, key + "." + e.key, "omega_dt keys", {"from", "to", "points", "values"});
    }
  }
  if (values) {
    if (from || to || points) {
      fail(axis, key, "give either values or from, to and points, not both");
    }
    return listed_values(*values, key + ".values", true);
  }
  if (!from) fail_missing(axis, key + ".from", "omega_dt needs from, to and points, or values");
  if (!to) fail_missing(axis, key + ".to", "omega_dt needs from, to and points, or values");
  if (!points) {
    fail_missing(axis, key + ".points",
                 "omega_dt needs points (the number of log-spaced values), or values");
  }
  const double lo = number(*from, key + ".from");
  const double hi = number(*to, key + ".to");
  if (!(lo > 0.0)) fail(*from, key + ".from", "must be > 0 (the values are log-spaced)");
  if (!(hi > 0.0)) fail(*to, key + ".to", "must be > 0 (the values are log-spaced)");
  if (lo == hi) fail(*to, key + ".to", "equals from; use values = [..] for a single value");
  const std::int64_t n = integer(*points, key + ".points");
  if (n < 2) fail(*points, key + ".points", "must be >= 2 (both ends are included)");
  if (n > kMaxGridPoints) {
    fail(*points, key + ".points", "must be <= " + std::to_string(kMaxGridPoints));
  }
  std::vector<double> out(static_cast<std::size_t>(n));
  const double step = std::log(hi / lo) / static_cast<double>(n - 1);
  for (std::int64_t i = 0; i + 1 < n; ++i) {
    out[static_cast<std::size_t>(i)] = lo * std::exp(static_cast<double>(i) * step);
  }
  out.front() = lo;
  out.back() = hi;  // exactly as written
  return out;
}

void PlanReader::check_spectral_sections() const {
  for (const char* section : {"scene", "method"}) {
    if (const toml::node* node = root_->get(section)) {
      fail(*node, section,
           "a spectral study runs no simulation; give each method in study.methods");
    }
  }
  if (const toml::node* output = root_->get("output"); output && output->is_table()) {
    for (const Entry& e : in_file_order(*output->as_table())) {
      if (e.key != "file") {
        fail(*e.node, "output." + e.key, "is not used by a spectral study (only output.file is)");
      }
    }
  }
}

}  // namespace impactid::plan_reading
