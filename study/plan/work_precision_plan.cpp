#include "study/plan/plan_reader.hpp"

namespace impactid::plan_reading {

void PlanReader::read_work_precision(const toml::table& study) {
  WorkPrecisionStudy& out = plan_->work_precision;
  const std::vector<std::string> known{"kind", "methods", "elements", "courant", "repeats"};
  for (const Entry& e : in_file_order(study)) {
    const std::string key = "study." + e.key;
    const toml::node& node = *e.node;
    if (e.key == "kind") {
    } else if (e.key == "methods") {
      out.methods = spectral_methods(node, key);
      methods_node_ = &node;
    } else if (e.key == "elements") {
      elements_node_ = &node;
      for (const double v : number_list(node, key, "element counts")) {
        out.elements.push_back(static_cast<long>(v));
      }
    } else if (e.key == "courant") {
      courant_node_ = &node;
      out.courant = number_list(node, key, "Courant numbers");
    } else if (e.key == "repeats") {
      const std::int64_t n = integer(node, key);
      if (n < 1 || n > kMaxRepeats) {
        fail(node, key, "must be an integer from 1 to " + std::to_string(kMaxRepeats));
      }
      out.repeats = static_cast<int>(n);
    } else if (e.key == "practical" || e.key == "axes" || e.key == "points") {
      fail(node, key,
           "is not a key of a work-precision study (it varies elements and courant, for each "
           "of its methods)");
    } else {
      fail_unknown(node, key, "work-precision keys", known);
    }
  }
  if (out.methods.empty()) out.methods = default_work_precision_methods();
  if (plan_->base.model) {
    // A model's mesh is fixed: its one "element count" is its DOF count.
    if (elements_node_) {
      fail(*elements_node_, "study.elements",
           "does not apply to a model (kind = \"matrices\"): its mesh is the user's; vary "
           "courant");
    }
    out.elements = {static_cast<long>(plan_->base.model->model->size())};
  }
  if (out.elements.empty()) out.elements = {50, 100, 200, 400, 800};
  if (out.courant.empty()) out.courant = {0.25, 0.5, 1.0, 2.0, 4.0};
  const long points =
      static_cast<long>(out.methods.size() * out.elements.size() * out.courant.size());
  if (points > kMaxGridPoints) {
    fail(study, "study",
         "has " + std::to_string(points) + " points, more than " + std::to_string(kMaxGridPoints));
  }
}

std::vector<SpectralMethod> PlanReader::default_work_precision_methods() {
  const auto make = [](MethodKind kind, std::vector<std::pair<const char*, double>> given,
                       std::string label) {
    SimulationSettings simulation;
    simulation.method.kind = kind;
    for (const auto& [name, value] : given) simulation.method.given.set(name, value);
    return SpectralMethod{std::get<Simulation>(build(simulation)).method, std::move(label),
                          simulation.method};
  };
  return {make(MethodKind::central_difference, {}, "cdm"),
          make(MethodKind::backward_euler, {}, "backward-euler"),
          make(MethodKind::newmark, {{"delta", 0.3}}, "newmark delta=0.3"),
          make(MethodKind::hht, {{"delta", 0.45}, {"alpha", -0.3}}, "hht alpha=-0.3 delta=0.45"),
          make(MethodKind::generalized_alpha, {{"rho_inf", 0.8}}, "generalized-alpha rho_inf=0.8")};
}

void PlanReader::check_work_precision_sections() const {
  if (const toml::node* node = root_->get("method")) {
    fail(*node, "method", "a work-precision study gives each method in study.methods");
  }
  if (const toml::node* scene = root_->get("scene"); scene && scene->is_table()) {
    for (const char* key : {"elements", "courant", "dt"}) {
      if (const toml::node* node = scene->as_table()->get(key)) {
        fail(*node, "scene."s + key,
             std::string("is set by the work-precision study: give ") +
                 (std::string_view(key) == "elements" ? "study.elements" : "study.courant") +
                 " instead");
      }
    }
  }
  if (const toml::node* output = root_->get("output"); output && output->is_table()) {
    for (const char* key : {"indicators", "histories"}) {
      if (const toml::node* node = output->as_table()->get(key)) {
        fail(*node, "output."s + key,
             "is not used by a work-precision study (its columns are fixed: results/README.md)");
      }
    }
  }
}

void PlanReader::check_work_precision() const {
  const WorkPrecisionStudy& wp = plan_->work_precision;
  for (std::size_t m = 0; m < wp.methods.size(); ++m) {
    for (const long n : wp.elements) {
      for (const double c : wp.courant) {
        SimulationSettings settings;
        std::optional<ParameterError> error =
            assign_work_precision_point(*plan_, static_cast<long>(m), n, c, settings);
        if (!error) {
          auto built = build(settings);
          if (auto* e = std::get_if<ParameterError>(&built)) error = *e;
        }
        if (!error) continue;
        const std::string suffix = " (at method " + wp.methods[m].label + ", elements " +
                                   std::to_string(n) + ", courant " + format_value(c) + ")";
        if (error->field == "elements" && elements_node_) {
          fail_at(*elements_node_, "study.elements", error->value, error->constraint + suffix);
        }
        if (error->field == "courant" && courant_node_) {
          fail_at(*courant_node_, "study.courant", error->value, error->constraint + suffix);
        }
        const ParameterInfo* info = find_parameter(error->field);
        if (info && info->group == ParameterGroup::method && methods_node_) {
          fail_at(*methods_node_, "study.methods", error->value, error->constraint + suffix);
        }
        fail_base(*error, suffix);
      }
    }
  }
}

}  // namespace impactid::plan_reading
