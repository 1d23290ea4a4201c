#include "core/model/model_scene.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/algebra/contact_lcp.hpp"
#include "core/model/rod_scene.hpp"

namespace impactid {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// G_k·x of contact k.
double contact_row(const ModelContact& c, const Eigen::VectorXd& x) {
  double g = 0.0;
  if (c.plus >= 0) g += x[c.plus];
  if (c.minus >= 0) g -= x[c.minus];
  return g;
}

bool is_zero(const Eigen::VectorXd& v) {
  return (v.array() == 0.0).all();
}

}  // namespace

double gershgorin_omega(const SparseMatrix& mass, const SparseMatrix& stiffness) {
  const Eigen::Index n = mass.rows();
  Eigen::VectorXd lumped = Eigen::VectorXd::Zero(n), row = Eigen::VectorXd::Zero(n);
  for (Eigen::Index j = 0; j < n; ++j) {
    for (SparseMatrix::InnerIterator it(mass, j); it; ++it) lumped[it.row()] += it.value();
    for (SparseMatrix::InnerIterator it(stiffness, j); it; ++it) {
      row[it.row()] += std::abs(it.value());
    }
  }
  double bound = 0.0;
  for (Eigen::Index i = 0; i < n; ++i) bound = std::max(bound, row[i] / lumped[i]);
  return std::sqrt(bound);
}

bool ModelScene::operator==(const ModelScene& other) const {
  return model == other.model && dt == other.dt && t_end == other.t_end &&
         rayleigh_mass == other.rayleigh_mass && rayleigh_stiffness == other.rayleigh_stiffness &&
         primary_contact == other.primary_contact;
}

std::optional<ParameterError> validate(const ModelScene& s) {
  if (!(s.dt > 0.0 && std::isfinite(s.dt))) {
    return ParameterError{"dt", format_value(s.dt), "must be positive and finite"};
  }
  if (!(s.t_end >= s.dt && std::isfinite(s.t_end))) {
    return ParameterError{"t_end", format_value(s.t_end), "must be finite and at least dt"};
  }
  // The rod's and the scenes' bounds on the grid (issue 38: a model with a tiny dt filled the
  // memory before anything said no).
  if (auto e = validate_time_grid("dt", s.dt, s.dt, s.t_end, "",
                                  static_cast<int>(s.model->contacts.size()))) {
    return e;
  }
  if (!(s.rayleigh_mass >= 0.0 && std::isfinite(s.rayleigh_mass))) {
    return ParameterError{"rayleigh_mass", format_value(s.rayleigh_mass),
                          "must be non-negative and finite"};
  }
  if (!(s.rayleigh_stiffness >= 0.0 && std::isfinite(s.rayleigh_stiffness))) {
    return ParameterError{"rayleigh_stiffness", format_value(s.rayleigh_stiffness),
                          "must be non-negative and finite"};
  }
  if (s.primary_contact) {
    bool found = false;
    std::string names;
    for (const ModelContact& c : s.model->contacts) {
      found = found || c.name == *s.primary_contact;
      names += (names.empty() ? "" : ", ") + c.name;
    }
    if (!found) {
      return ParameterError{"primary_contact", '"' + *s.primary_contact + '"',
                            "is not a contact of the model (its contacts: " + names + ")"};
    }
  }
  return std::nullopt;
}

int primary_contact_index(const ModelScene& s) {
  const auto& contacts = s.model->contacts;
  for (std::size_t k = 0; k < contacts.size() && s.primary_contact; ++k) {
    if (contacts[k].name == *s.primary_contact) return static_cast<int>(k);
  }
  return 0;
}

AssembledScene assemble(const ModelScene& s) {
  const Model& model = *s.model;
  AssembledScene out;
  SparseMatrix damping =
      model.damping.rows() == 0 ? SparseMatrix(model.size(), model.size()) : model.damping;
  if (s.rayleigh_mass != 0.0) damping += s.rayleigh_mass * model.mass;
  if (s.rayleigh_stiffness != 0.0) damping += s.rayleigh_stiffness * model.stiffness;
  damping.prune(0.0);

  out.initial_velocity = model.initial_velocity;
  if (!is_zero(model.initial_displacement)) out.initial_displacement = model.initial_displacement;
  out.dt = s.dt;
  out.step_count = step_count(s.t_end, s.dt);
  out.primary = primary_contact_index(s);
  for (const ModelContact& c : model.contacts) out.probes.push_back({c.area, c.velocity_dof});

  // Rigid flight: nothing deforms or damps a body moving at v0 (exact zeros, as K·1 = 0 of a rod).
  Eigen::VectorXd product = Eigen::VectorXd::Zero(model.size());
  multiply_add(model.stiffness, 1.0, model.initial_velocity, product);
  multiply_add(damping, 1.0, model.initial_velocity, product);
  // A load accelerates the model from the start: no flight is u = v0·t then.
  out.rigid_flight =
      out.initial_displacement.size() == 0 && is_zero(product) && !model.load.active();
  out.first_contact_time = kInf;
  for (const ModelContact& c : model.contacts) {
    const double rate = contact_row(c, model.initial_velocity);
    if (rate > 0.0) out.first_contact_time = std::min(out.first_contact_time, c.gap / rate);
  }
  if (!out.rigid_flight) out.first_contact_time = 0.0;

  std::vector<Constraint> constraints;
  for (const ModelContact& c : model.contacts) constraints.push_back({c.plus, c.minus, c.gap});
  const std::optional<Tridiagonal> mass = as_tridiagonal(model.mass);
  const std::optional<Tridiagonal> stiffness = as_tridiagonal(model.stiffness);
  const std::optional<Tridiagonal> damping_t = as_tridiagonal(damping);
  if (mass && stiffness && damping_t &&
      constraints.size() <= static_cast<std::size_t>(kMaxConstraints)) {
    SecondOrderSystem& system = out.system;
    system.mass = *mass;
    system.stiffness = *stiffness;
    system.damping = *damping_t;
    const Constraint& first = constraints.front();
    if (constraints.size() == 1 && first.plus >= 0 && first.minus < 0) {
      // The paper's form: the named contact, whose operations the built-in rod runs.
      system.contact_dof = first.plus;
      system.gap = first.gap;
      out.contact_columns = true;
    } else {
      system.constraints = std::move(constraints);
    }
    system.load = model.load;
    return out;
  }
  auto sparse = std::make_shared<SparseSystem>();
  sparse->mass = model.mass;
  sparse->stiffness = model.stiffness;
  sparse->damping = std::move(damping);
  sparse->constraints = std::move(constraints);
  sparse->load = model.load;
  out.sparse = std::move(sparse);
  return out;
}

ModelUnits model_units(const std::string& text) {
  std::vector<std::string> words;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t end = std::min(text.find(',', start), text.size());
    std::string word = text.substr(start, end - start);
    word.erase(0, word.find_first_not_of(' '));
    word.erase(word.find_last_not_of(' ') + 1);
    words.push_back(word);
    start = end + 1;
  }
  for (const std::string& w : words) {
    if (w.empty() || w.find_first_of(" \t") != std::string::npos) return {};
  }
  if (words.size() != 4) return {};
  return {words[0], words[1], words[2], words[3]};
}

}  // namespace impactid
