#include "study/plan/model_file.hpp"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>

#include "core/model/sparse_factorization.hpp"
#include "study/formats/hdf5_file.hpp"
#include "study/formats/matrix_market.hpp"
#include "study/plan/toml_reading.hpp"

namespace impactid {
namespace {

using toml_reading::ordered;

// A progress line on stderr for a large file (more than 2^20 entries), when stderr is a terminal.
MatrixMarketProgress progress_line(const std::filesystem::path& path) {
  if (!isatty(STDERR_FILENO)) return {};
  return [name = path.filename().string()](long read, long total) {
    if (total < (1L << 20)) return;
    std::fprintf(stderr, "\rreading %s: %ld of %ld entries (%.0f%%)%s", name.c_str(), read, total,
                 100.0 * static_cast<double>(read) / static_cast<double>(total),
                 read >= total ? "\n" : "");
  };
}

// The largest |A(i,j) − A(j,i)|, relative to the largest |A|, and where.
struct Asymmetry {
  double relative = 0.0;
  Eigen::Index row = 0, col = 0;
  double value = 0.0, mirror = 0.0;
};
Asymmetry asymmetry(const SparseMatrix& a) {
  const SparseMatrix t = a.transpose();
  const SparseMatrix diff = a - t;
  double scale = 0.0;
  for (Eigen::Index j = 0; j < a.outerSize(); ++j) {
    for (SparseMatrix::InnerIterator it(a, j); it; ++it)
      scale = std::max(scale, std::abs(it.value()));
  }
  Asymmetry out;
  for (Eigen::Index j = 0; j < diff.outerSize(); ++j) {
    for (SparseMatrix::InnerIterator it(diff, j); it; ++it) {
      const double r = scale > 0.0 ? std::abs(it.value()) / scale : 0.0;
      if (r > out.relative)
        out = {r, it.row(), it.col(), a.coeff(it.row(), it.col()), t.coeff(it.row(), it.col())};
    }
  }
  return out;
}

class ModelReader : public toml_reading::TableReader {
 public:
  ModelReader(const TableFail& fail, std::string prefix, std::filesystem::path directory)
      : TableReader(fail), prefix_(std::move(prefix)), directory_(std::move(directory)) {}

  std::filesystem::path path(const toml::node& node, const std::string& key) const {
    const std::string name = string(node, key);
    if (name.empty()) fail(node, key, "must name a file");
    std::filesystem::path p(name);
    if (!p.is_absolute()) p = directory_ / p;
    // A device or a folder would be read without end (/dev/zero) or fail obscurely.
    std::error_code ec;
    if (std::filesystem::exists(p, ec) && !std::filesystem::is_regular_file(p, ec)) {
      fail(node, key, p.string() + ": is not a regular file");
    }
    return p;
  }

  // A square, symmetric matrix of a file, of size n when n >= 0.
  SparseMatrix matrix(const toml::node& node, const std::string& key, Eigen::Index n) const {
    const std::filesystem::path file = path(node, key);
    SparseMatrix a;
    try {
      a = read_matrix_market(file, progress_line(file));
    } catch (const MatrixMarketError& e) {
      fail(node, key, e.what());
    }
    const std::string where = file.string() + ": ";
    if (a.rows() != a.cols()) {
      fail(node, key,
           where + "is not square: " + std::to_string(a.rows()) + " rows, " +
               std::to_string(a.cols()) + " columns");
    }
    if (n >= 0 && a.rows() != n) {
      fail(node, key,
           where + "has " + std::to_string(a.rows()) + " rows, where the mass matrix has " +
               std::to_string(n));
    }
    const Asymmetry s = asymmetry(a);
    if (s.relative > 1e-12) {
      fail(node, key,
           where + "is not symmetric: entry (" + std::to_string(s.row + 1) + ", " +
               std::to_string(s.col + 1) + ") is " + format_value(s.value) + " and (" +
               std::to_string(s.col + 1) + ", " + std::to_string(s.row + 1) + ") is " +
               format_value(s.mirror) + " (1-based, as in the file)");
    }
    // Exactly symmetric: the factorisations read one triangle, the products both.
    SparseMatrix sym = SparseMatrix(0.5 * (a + SparseMatrix(a.transpose())));
    sym.prune(0.0);
    return sym;
  }

  Eigen::Index dof(const toml::node& node, const std::string& key, Eigen::Index n) const {
    const auto* i = node.as_integer();
    if (!i) fail(node, key, "must be a DOF: an integer from 0 (DOFs count from 0)");
    if (i->get() < 0 || i->get() >= n) {
      fail(node, key,
           "DOF " + std::to_string(i->get()) + " is out of range: the model has " +
               std::to_string(n) + " DOFs, 0 to " + std::to_string(n - 1));
    }
    return static_cast<Eigen::Index>(i->get());
  }

  // A set of DOFs: a list, "all", a slice "start:stop:step", or the name of a [scene.dof_sets]
  // entry (when `sets` is given).
  std::vector<Eigen::Index> dof_set(const toml::node& node, const std::string& key, Eigen::Index n,
                                    const toml::table* sets) const {
    if (const auto* array = node.as_array()) {
      std::vector<Eigen::Index> out;
      for (std::size_t k = 0; k < array->size(); ++k) {
        out.push_back(dof((*array)[k], key + "." + std::to_string(k + 1), n));
      }
      return out;
    }
    const std::string text = string(node, key);
    if (text == "all") return slice(node, key, n, "::");
    if (text.find(':') != std::string::npos) return slice(node, key, n, text);
    if (sets) {
      if (const toml::node* set = sets->get(text)) {
        return dof_set(*set, prefix_ + ".dof_sets." + text, n, nullptr);
      }
    }
    fail(node, key,
         "\"" + text +
             "\" is not a set of DOFs: give a list, \"all\", a slice "
             "\"start:stop:step\", or the name of a [" +
             prefix_ + ".dof_sets] entry");
  }

  std::vector<Eigen::Index> slice(const toml::node& node, const std::string& key, Eigen::Index n,
                                  const std::string& text) const {
    std::vector<std::string> fields(1);
    for (const char ch : text) {
      if (ch == ':')
        fields.emplace_back();
      else
        fields.back() += ch;
    }
    if (fields.size() < 2 || fields.size() > 3) {
      fail(node, key, "\"" + text + "\" is not a slice start:stop:step");
    }
    long parts[3] = {0, static_cast<long>(n), 1};
    for (std::size_t k = 0; k < fields.size(); ++k) {
      if (fields[k].empty()) continue;
      char* stop = nullptr;
      parts[k] = std::strtol(fields[k].c_str(), &stop, 10);
      if (*stop != '\0') fail(node, key, "\"" + text + "\" is not a slice start:stop:step");
    }
    if (parts[2] <= 0) fail(node, key, "\"" + text + "\": the step must be positive");
    const long begin = std::clamp(parts[0] < 0 ? parts[0] + n : parts[0], 0L, static_cast<long>(n));
    const long stop = std::clamp(parts[1] < 0 ? parts[1] + n : parts[1], 0L, static_cast<long>(n));
    std::vector<Eigen::Index> out;
    for (long i = begin; i < stop; i += parts[2]) out.push_back(i);
    if (out.empty()) fail(node, key, "\"" + text + "\" selects no DOF of the " + std::to_string(n));
    return out;
  }

  // An initial vector: a Matrix Market vector file, or { value, dofs }.
  Eigen::VectorXd initial(const toml::node& node, const std::string& key, Eigen::Index n,
                          const toml::table* sets) const {
    Eigen::VectorXd out = Eigen::VectorXd::Zero(n);
    if (node.is_string()) {
      const std::filesystem::path file = path(node, key);
      try {
        out = read_matrix_market_vector(file);
      } catch (const MatrixMarketError& e) {
        fail(node, key, e.what());
      }
      if (out.size() != n) {
        fail(node, key,
             file.string() + ": has " + std::to_string(out.size()) +
                 " entries, where the model has " + std::to_string(n) + " DOFs");
      }
      return out;
    }
    const toml::table& t =
        table(node, key, "must be a Matrix Market vector file or { value = ..., dofs = ... }");
    const toml::node* value = t.get("value");
    const toml::node* dofs = t.get("dofs");
    for (const auto& [k, v] : ordered(t)) {
      if (k != "value" && k != "dofs") fail(*v, key + "." + k, "unknown key (value, dofs)");
    }
    if (!value) fail(node, key + ".value", "is missing: the value over the DOFs");
    const double x = number(*value, key + ".value");
    const std::vector<Eigen::Index> set =
        dofs ? dof_set(*dofs, key + ".dofs", n, sets) : slice(node, key, n, "::");
    for (const Eigen::Index i : set) out[i] = x;
    return out;
  }

  ModelContact contact(const toml::table& t, const std::string& at, Eigen::Index n) const {
    ModelContact c;
    const toml::node *dof_node = nullptr, *dofs_node = nullptr, *side_node = nullptr,
                     *velocity_node = nullptr;
    std::string side = "upper";
    for (const auto& [key, node] : ordered(t)) {
      const std::string path = at + "." + key;
      if (key == "name") {
        c.name = string(*node, path);
        const bool ok = !c.name.empty() && c.name.find_first_not_of(
                                               "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVW"
                                               "XYZ0123456789_-") == std::string::npos;
        if (!ok) fail(*node, path, "must be letters, digits, '_' or '-'");
      } else if (key == "dof") {
        dof_node = node;
        c.plus = dof(*node, path, n);
      } else if (key == "dofs") {
        dofs_node = node;
        const auto* pair = node->as_array();
        if (!pair || pair->size() != 2)
          fail(*node, path, "must be a pair of DOFs [i, j]: u_i − u_j <= gap");
        c.plus = dof((*pair)[0], path + ".1", n);
        c.minus = dof((*pair)[1], path + ".2", n);
        if (c.plus == c.minus) fail(*node, path, "must be two different DOFs");
      } else if (key == "side") {
        side_node = node;
        side = string(*node, path);
        if (side != "upper" && side != "lower") {
          fail(*node, path,
               "\"" + side + "\" is not a side: \"upper\" (u <= gap) or \"lower\" (u >= -gap)");
        }
      } else if (key == "gap") {
        c.gap = number(*node, path);
        if (c.gap < 0.0) fail(*node, path, format_value(c.gap) + ": a gap must be >= 0");
      } else if (key == "area") {
        c.area = number(*node, path);
        if (!(c.area > 0.0)) fail(*node, path, format_value(c.area) + ": an area must be > 0");
      } else if (key == "velocity_dof") {
        velocity_node = node;
        c.velocity_dof = dof(*node, path, n);
      } else {
        fail(*node, path,
             "unknown key (contact keys: name, dof, side, dofs, gap, area, velocity_dof)");
      }
    }
    if (c.name.empty()) fail(t, at + ".name", "is missing: every contact needs a name");
    if (!dof_node && !dofs_node)
      fail(t, at + ".dof", "is missing: give dof (a wall) or dofs (a pair)");
    if (dof_node && dofs_node) fail(*dofs_node, at + ".dofs", "cannot be given with dof");
    if (dofs_node && side_node)
      fail(*side_node, at + ".side", "applies to a wall (dof), not a pair");
    if (!velocity_node) c.velocity_dof = c.plus;
    if (dof_node && side == "lower") {
      c.minus = c.plus;
      c.plus = -1;
    }
    return c;
  }

 private:
  std::string prefix_;
  std::filesystem::path directory_;
};

// The reference history of a CSV file: a header `t,<contact>.pressure,<contact>.velocity,...`
// (any subset of the contacts, any order), then rows of numbers; '#' starts a comment line.
ReferenceHistory read_reference_csv(const std::filesystem::path& file, const Model& model) {
  std::ifstream in(file);
  if (!in) throw MatrixMarketError(file.string() + ": cannot be opened");
  ReferenceHistory out;
  out.source = file.string();
  out.contacts.resize(model.contacts.size());
  std::vector<std::vector<double>*> columns;
  std::string line;
  long number = 0;
  bool header = false;
  const auto error = [&](const std::string& what) {
    throw MatrixMarketError(file.string() + ":" + std::to_string(number) + ": " + what);
  };
  while (std::getline(in, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> cells;
    std::stringstream row(line);
    for (std::string cell; std::getline(row, cell, ',');) {
      const auto b = cell.find_first_not_of(" \t"), e = cell.find_last_not_of(" \t");
      cells.push_back(b == std::string::npos ? "" : cell.substr(b, e - b + 1));
    }
    if (!header) {
      header = true;
      if (cells.empty() || cells[0] != "t")
        // Not a reference history: nothing of the file is echoed (as for a Matrix Market file).
        error("is not a reference history: its header's first column must be t");
      columns.push_back(&out.t);
      for (std::size_t c = 1; c < cells.size(); ++c) {
        const std::size_t dot = cells[c].rfind('.');
        const std::string name = cells[c].substr(0, dot),
                          what = dot == std::string::npos ? "" : cells[c].substr(dot + 1);
        std::size_t k = 0;
        while (k < model.contacts.size() && model.contacts[k].name != name) ++k;
        if (k == model.contacts.size() || (what != "pressure" && what != "velocity")) {
          error("column \"" + cells[c] +
                "\" is not <contact>.pressure or <contact>.velocity of a contact of the model");
        }
        columns.push_back(what == "pressure" ? &out.contacts[k].pressure
                                             : &out.contacts[k].velocity);
      }
      continue;
    }
    if (cells.size() != columns.size()) {
      error(std::to_string(cells.size()) + " values, where the header has " +
            std::to_string(columns.size()));
    }
    for (std::size_t c = 0; c < cells.size(); ++c) {
      char* end = nullptr;
      const double v = std::strtod(cells[c].c_str(), &end);
      if (cells[c].empty() || *end != '\0' || !std::isfinite(v))
        error("\"" + cells[c] + "\" is not a finite number");
      columns[c]->push_back(v);
    }
    if (out.t.size() > 1 && !(out.t.back() > out.t[out.t.size() - 2]))
      error("t must increase: " + format_value(out.t.back()));
  }
  if (out.t.empty()) error("has no samples");
  return out;
}

// The reference history of an HDF5 file: a dataset t and, for any subset of the contacts, one
// dataset per contact and quantity, named <contact>.pressure and <contact>.velocity as the CSV
// file's columns are, or pressure.<contact> and velocity.<contact> as impactid's own history
// files name them (`impactid simulate --history FILE.h5` of a finer run is a reference as it is).
ReferenceHistory read_reference_hdf5(const std::filesystem::path& file, const Model& model) {
  ReferenceHistory out;
  out.source = file.string();
  out.contacts.resize(model.contacts.size());
  const auto error = [&](const std::string& what) {
    throw MatrixMarketError(file.string() + ": " + what);
  };
  try {
    const Hdf5Reader in(file);
    if (!in.exists("t")) error("has no dataset t (the sample times)");
    out.t = in.doubles("t");
    if (out.t.empty()) error("t has no samples");
    for (std::size_t i = 0; i < out.t.size(); ++i) {
      if (!std::isfinite(out.t[i])) error("t[" + std::to_string(i) + "] is not finite");
      if (i > 0 && !(out.t[i] > out.t[i - 1]))
        error("t must increase: t[" + std::to_string(i) + "] = " + format_value(out.t[i]));
    }
    bool any = false;
    for (std::size_t k = 0; k < model.contacts.size(); ++k) {
      const std::string& name = model.contacts[k].name;
      for (const char* what : {"pressure", "velocity"}) {
        std::string dataset = name + "." + what;
        if (!in.exists(dataset)) dataset = std::string(what) + "." + name;
        if (!in.exists(dataset)) continue;
        std::vector<double> values = in.doubles(dataset);
        if (values.size() != out.t.size()) {
          error(dataset + " has " + std::to_string(values.size()) + " samples, t has " +
                std::to_string(out.t.size()));
        }
        for (std::size_t i = 0; i < values.size(); ++i) {
          if (!std::isfinite(values[i]))
            error(dataset + "[" + std::to_string(i) + "] = " + format_value(values[i]) +
                  " is not a finite number");
        }
        (std::string_view(what) == "pressure" ? out.contacts[k].pressure
                                              : out.contacts[k].velocity) = std::move(values);
        any = true;
      }
    }
    if (!any) {
      error(
          "has no dataset <contact>.pressure or <contact>.velocity (or pressure.<contact>, "
          "velocity.<contact>) of a contact of the model");
    }
  } catch (const Hdf5Error& e) {
    throw MatrixMarketError(e.what());
  }
  return out;
}

}  // namespace

bool is_model_scene(const toml::table& scene) {
  const toml::node* kind = scene.get("kind");
  return kind && kind->is_string() && kind->as_string()->get() == "matrices";
}

bool is_model_scene_key(const std::string& key) {
  for (const char* k : {"kind", "units", "primary_contact", "matrices", "dof_sets", "initial",
                        "load", "contact", "reference"}) {
    if (key == k) return true;
  }
  return false;
}

ModelScene read_model_scene(const toml::table& scene, const std::string& prefix,
                            const std::filesystem::path& directory, const TableFail& fail) {
  const ModelReader r(fail, prefix, directory);
  auto model = std::make_shared<Model>();
  ModelScene out;
  const toml::node* matrices = scene.get("matrices");
  if (!matrices) {
    r.fail(scene, prefix + ".matrices",
           "is missing: a model needs [" + prefix + ".matrices] with mass and stiffness files");
  }
  const toml::table& m =
      r.table(*matrices, prefix + ".matrices", "must be a table (mass, stiffness, damping)");
  for (const auto& [key, node] : ordered(m)) {
    if (key != "mass" && key != "stiffness" && key != "damping") {
      r.fail(*node, prefix + ".matrices." + key, "unknown key (mass, stiffness, damping)");
    }
  }
  const toml::node* mass = m.get("mass");
  const toml::node* stiffness = m.get("stiffness");
  if (!mass) r.fail(m, prefix + ".matrices.mass", "is missing: the mass matrix file");
  if (!stiffness)
    r.fail(m, prefix + ".matrices.stiffness", "is missing: the stiffness matrix file");
  model->mass = r.matrix(*mass, prefix + ".matrices.mass", -1);
  const Eigen::Index n = model->mass.rows();
  {
    SparseFactorization f;
    if (!f.factor(model->mass)) {
      r.fail(*mass, prefix + ".matrices.mass",
             r.path(*mass, prefix + ".matrices.mass").string() +
                 ": is not positive definite: pivot " + format_value(f.failed_pivot()) +
                 " at DOF " + std::to_string(f.failed_dof()) + " (row " +
                 std::to_string(f.failed_dof() + 1) + " of the file)");
    }
  }
  model->stiffness = r.matrix(*stiffness, prefix + ".matrices.stiffness", n);
  if (const toml::node* damping = m.get("damping")) {
    model->damping = r.matrix(*damping, prefix + ".matrices.damping", n);
  }
  model->source = r.path(*mass, "").string() + ", " + r.path(*stiffness, "").string();
  model->omega_bound = gershgorin_omega(model->mass, model->stiffness);

  const toml::table* sets = nullptr;
  if (const toml::node* s = scene.get("dof_sets")) {
    sets = &r.table(*s, prefix + ".dof_sets", "must be a table of named DOF sets");
    for (const auto& [key, node] : ordered(*sets))
      r.dof_set(*node, prefix + ".dof_sets." + key, n, nullptr);
  }
  model->initial_displacement = Eigen::VectorXd::Zero(n);
  model->initial_velocity = Eigen::VectorXd::Zero(n);
  if (const toml::node* initial = scene.get("initial")) {
    const toml::table& t =
        r.table(*initial, prefix + ".initial", "must be a table (displacement, velocity)");
    for (const auto& [key, node] : ordered(t)) {
      const std::string at = prefix + ".initial." + key;
      if (key == "displacement")
        model->initial_displacement = r.initial(*node, at, n, sets);
      else if (key == "velocity")
        model->initial_velocity = r.initial(*node, at, n, sets);
      else
        r.fail(*node, at, "unknown key (displacement, velocity)");
    }
  }
  if (const toml::node* load = scene.get("load")) {
    const toml::table& t =
        r.table(*load, prefix + ".load", "must be a table (force, potential_at_rest)");
    const toml::node* force = t.get("force");
    if (!force) {
      r.fail(*load, prefix + ".load.force",
             "is missing: the constant force on every DOF (a Matrix Market vector file of n "
             "entries, or { value = ..., dofs = ... })");
    }
    for (const auto& [key, node] : ordered(t)) {
      const std::string at = prefix + ".load." + key;
      if (key == "force")
        model->load.force = r.initial(*node, at, n, sets);
      else if (key == "potential_at_rest")
        model->load.rest_potential = r.number(*node, at);
      else
        r.fail(*node, at, "unknown key (force, potential_at_rest)");
    }
  }
  if (const toml::node* units = scene.get("units"))
    model->units = r.string(*units, prefix + ".units");

  const toml::node* contacts = scene.get("contact");
  const auto* array = contacts ? contacts->as_array() : nullptr;
  if (!array || array->empty() || !array->is_array_of_tables()) {
    r.fail(contacts ? *contacts : static_cast<const toml::node&>(scene), prefix + ".contact",
           "a model needs at least one [[" + prefix + ".contact]] table");
  }
  std::vector<std::pair<Eigen::Index, std::string>> walls;  // DOF, contact name
  for (std::size_t k = 0; k < array->size(); ++k) {
    const std::string at = prefix + ".contact." + std::to_string(k + 1);
    const toml::table& t = *(*array)[k].as_table();
    ModelContact c = r.contact(t, at, n);
    for (const ModelContact& other : model->contacts) {
      if (other.name == c.name) r.fail(t, at + ".name", "\"" + c.name + "\" names two contacts");
      if (other.plus == c.plus && other.minus == c.minus) {
        r.fail(
            t, at,
            "contact \"" + c.name + "\" repeats the constraint of contact \"" + other.name + "\"");
      }
    }
    if ((c.plus < 0) != (c.minus < 0)) {  // a wall
      const Eigen::Index d = c.plus >= 0 ? c.plus : c.minus;
      for (const auto& [dof, name] : walls) {
        if (dof == d) {
          r.fail(t, at + ".dof",
                 "DOF " + std::to_string(d) + " already has a wall (contact \"" + name +
                     "\"): two walls on one DOF make the contact problem singular");
        }
      }
      walls.emplace_back(d, c.name);
    }
    model->contacts.push_back(std::move(c));
  }
  if (const toml::node* primary = scene.get("primary_contact")) {
    out.primary_contact = r.string(*primary, prefix + ".primary_contact");
    bool found = false;
    for (const ModelContact& c : model->contacts) found = found || c.name == *out.primary_contact;
    if (!found)
      r.fail(*primary, prefix + ".primary_contact",
             "\"" + *out.primary_contact + "\" is not a contact of the model");
  }
  if (const toml::node* reference = scene.get("reference")) {
    const toml::table& t = r.table(*reference, prefix + ".reference", "must be a table (file)");
    for (const auto& [key, node] : ordered(t)) {
      if (key != "file") r.fail(*node, prefix + ".reference." + key, "unknown key (file)");
    }
    const toml::node* file = t.get("file");
    if (!file) {
      r.fail(t, prefix + ".reference.file", "is missing: the reference history (CSV or HDF5)");
    }
    const std::filesystem::path path = r.path(*file, prefix + ".reference.file");
    const std::string ext = path.extension().string();
    if (ext != ".csv" && ext != ".h5" && ext != ".hdf5") {
      r.fail(*file, prefix + ".reference.file",
             "unknown format (a reference history is a .csv, .h5 or .hdf5 file)");
    }
    try {
      model->reference =
          ext == ".csv" ? read_reference_csv(path, *model) : read_reference_hdf5(path, *model);
    } catch (const MatrixMarketError& e) {
      r.fail(*file, prefix + ".reference.file", e.what());
    }
  }
  out.model = std::move(model);
  return out;
}

}  // namespace impactid
