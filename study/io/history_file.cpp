#include "study/io/history_file.hpp"

#include <array>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "core/reference/chain_exact.hpp"
#include "core/reference/clamped_bar_exact.hpp"
#include "core/reference/exact_solution.hpp"
#include "core/run/references.hpp"
#include "study/formats/hdf5_file.hpp"
#include "study/formats/text_file.hpp"

namespace impactid {
namespace {

using Column = HistoryColumn;

std::vector<Column> rod_history_columns(const RodScene& scene, const ContactTrace& trace) {
  const RodSceneDerived d = derive(scene);
  const RodImpactExact exact(scene);
  const auto n = static_cast<std::size_t>(trace.size());
  std::vector<Column> columns{
      {"t", "s", "sample time t_i = i*dt", {}},
      {"pressure", "MPa", "contact pressure lambda/A", trace.pressure},
      {"velocity", "mm/s", "contact-node velocity, positive toward the wall", trace.velocity},
      {"displacement", "mm", "contact-node displacement", trace.displacement},
      {"energy", "mJ",
       "kinetic + strain energy (cdm within its explicit limit: its own discrete energy)",
       trace.energy},
      {"exact_pressure", "MPa", "d'Alembert solution (mean of the limits on a jump)", {}},
      {"exact_velocity", "mm/s", "d'Alembert solution (mean of the limits on a jump)", {}},
      {"exact_displacement", "mm", "d'Alembert solution", {}},
  };
  for (std::size_t i = 0; i < n; ++i) {
    const long sample = static_cast<long>(i) + 1;
    const ContactNodeValues e = exact.at_sample(sample);
    columns[0].values.push_back(sample * d.time_step);
    columns[5].values.push_back(e.pressure);
    columns[6].values.push_back(e.velocity);
    columns[7].values.push_back(e.displacement);
  }
  // Last, so that the columns of a single-wall file keep their positions.
  if (scene.far_gap) {
    columns.push_back({"far_pressure", "MPa", "far-wall pressure lambda_0/A at node 0 (far_gap)",
                       trace.far_pressure});
  }
  return columns;
}

// A scene of bodies: the primary contact's samples and exact values under the rod's column
// names (a plot of one contact reads the same file either way), then every contact's, named
// "<column>.<contact>".
std::vector<Column> bodies_history_columns(const Scene& scene, const ContactTrace& trace, double dt,
                                           const ReferenceOptions& options) {
  const std::vector<SceneContact> contacts = scene_contacts(scene);
  const int primary = derive(scene).primary_contact;
  const auto n = static_cast<std::size_t>(trace.size());
  const SceneReference exact = scene_reference(scene, options);
  const std::string reference = exact.description() + " (mean of the limits on a jump)";
  std::vector<Column> columns{
      {"t", "s", "sample time t_i = i*dt", {}},
      {"pressure", "MPa", "primary contact's pressure lambda/A", trace.pressure},
      {"velocity", "mm/s", "primary contact's node velocity, +x positive", trace.velocity},
      {"displacement", "mm", "primary contact's node displacement", trace.displacement},
      {"energy", "mJ",
       "kinetic + strain energy (cdm within its explicit limit: its own discrete energy)",
       trace.energy},
      {"exact_pressure", "MPa", reference, {}},
      {"exact_velocity", "mm/s", reference, {}},
      {"exact_displacement", "mm", reference, {}},
  };
  for (std::size_t i = 0; i < n; ++i) {
    const auto p = static_cast<std::size_t>(primary);
    columns[0].values.push_back(static_cast<double>(i + 1) * dt);
    columns[5].values.push_back(exact.contacts[p].pressure[i]);
    columns[6].values.push_back(exact.contacts[p].velocity[i]);
  }
  // The displacement of an exact solution (not of a converged reference).
  const auto bar_displacement = [&](const auto& bar) {
    for (std::size_t i = 0; i < n; ++i) {
      const double t = static_cast<double>(i + 1) * dt;
      columns[7].values.push_back(bar.at(t, 1e-6 * dt).displacement);
    }
  };
  if (exact.refinements == 0 && exact.exact == SceneExact::clamped_bar) {
    bar_displacement(ClampedBarExact(*clamped_bar_params(scene)));
  } else if (exact.refinements == 0 && exact.exact == SceneExact::bouncing_bar) {
    bar_displacement(BouncingBarExact(*bouncing_bar_params(scene)));
  } else if (exact.refinements == 0) {
    const ChainExact chain(scene, static_cast<double>(n) * dt);
    for (std::size_t i = 0; i < n; ++i) {
      const double t = static_cast<double>(i + 1) * dt;
      columns[7].values.push_back(chain.at(primary, t, 1e-6 * dt).displacement);
    }
  } else {
    columns[7].values.assign(n, std::numeric_limits<double>::quiet_NaN());
  }
  for (std::size_t k = 0; k < contacts.size(); ++k) {
    const std::string& name = contacts[k].name;
    Column exact_p{"exact_pressure." + name, "MPa", reference, exact.contacts[k].pressure};
    Column exact_v{"exact_velocity." + name, "mm/s", reference, exact.contacts[k].velocity};
    columns.push_back({"pressure." + name, "MPa", "pressure lambda/A at contact " + name,
                       trace.contact_pressure[k]});
    columns.push_back({"velocity." + name, "mm/s",
                       "velocity of the node of contact " + name + ", +x positive",
                       trace.contact_velocity[k]});
    columns.push_back(std::move(exact_p));
    columns.push_back(std::move(exact_v));
  }
  return columns;
}

// A user's model: the primary contact's samples under the rod's column names, then every
// contact's, with the reference's samples as reference_pressure.<contact>, … (no exact solution:
// a model's reference is supplied or converged, core/reference/model_reference.hpp). Units are the
// model's.
std::vector<Column> model_history_columns(const ModelScene& scene, const ContactTrace& trace,
                                          const ModelReference& reference) {
  const Model& model = *scene.model;
  const auto n = static_cast<std::size_t>(trace.size());
  const std::string units = model.units.empty() ? "model units" : model.units;
  // The scene's units when its `units` names them (core/model/model_scene.hpp: model_units), else
  // none.
  const ModelUnits u = model_units(model.units);
  std::vector<Column> columns{
      {"t", u.time, "sample time t_i = i*dt", {}},
      {"pressure", u.pressure(), "primary contact's pressure lambda/area (" + units + ")",
       trace.pressure},
      {"velocity", u.velocity(), "primary contact's velocity DOF (" + units + ")", trace.velocity},
      {"displacement", u.length, "primary contact's velocity DOF's displacement",
       trace.displacement},
      {"energy", u.energy(),
       "kinetic + strain energy (cdm within its explicit limit: its own discrete energy)",
       trace.energy},
  };
  for (std::size_t i = 0; i < n; ++i)
    columns[0].values.push_back(static_cast<double>(i + 1) * scene.dt);
  const std::string description = reference.description();
  for (std::size_t k = 0; k < model.contacts.size(); ++k) {
    const std::string& name = model.contacts[k].name;
    columns.push_back({"pressure." + name, u.pressure(), "pressure lambda/area at contact " + name,
                       trace.contact_pressure[k]});
    columns.push_back({"velocity." + name, u.velocity(),
                       "velocity of the velocity DOF of contact " + name,
                       trace.contact_velocity[k]});
    const bool has = k < reference.contacts.size() && !reference.contacts[k].pressure.empty();
    const std::vector<double> none(n, std::numeric_limits<double>::quiet_NaN());
    columns.push_back({"reference_pressure." + name, u.pressure(), description,
                       has ? reference.contacts[k].pressure : none});
    columns.push_back({"reference_velocity." + name, u.velocity(), description,
                       has ? reference.contacts[k].velocity : none});
  }
  return columns;
}

void write_csv(const std::filesystem::path& path, const std::vector<Column>& columns) {
  try {
    write_text_atomically(path, [&](std::ostream& out) {
      out.precision(17);
      for (std::size_t c = 0; c < columns.size(); ++c) {
        out << (c ? "," : "") << columns[c].name << '[' << columns[c].units << ']';
      }
      out << '\n';
      for (std::size_t i = 0; i < columns[0].values.size(); ++i) {
        for (std::size_t c = 0; c < columns.size(); ++c) {
          out << (c ? "," : "") << columns[c].values[i];
        }
        out << '\n';
      }
    });
  } catch (const TextFileError& e) {
    throw HistoryFileError(e.what());
  }
}

void write_hdf5(const std::filesystem::path& path, const std::vector<Column>& columns,
                const Simulation& simulation) {
  try {
    Hdf5Writer file(path);
    file.attribute("/", "method", std::string(to_string(kind_of(simulation.method))));
    for (const ParameterInfo& info : parameter_table()) {
      if (info.kind == ParameterKind::choice) continue;
      if (const auto value = numeric_value(simulation, info.name)) {
        file.attribute("/", info.name, *value);
      }
    }
    // Derived coefficients that are no parameter (generalized-alpha's alpha_m and alpha_f), as
    // impactid simulate --json prints them.
    for (const ReportedValue& v : descriptor(simulation.method).values(simulation.method)) {
      if (!find_parameter(v.name)) file.attribute("/", v.name, v.value);
    }
    const Hdf5Dims dims{columns[0].values.size()};
    for (const Column& c : columns) {
      file.dataset(c.name, c.values, dims);
      file.attribute(c.name, "units", c.units);
      file.attribute(c.name, "long_name", c.description);
    }
    file.dimension_scale("t", "t");
    for (std::size_t c = 1; c < columns.size(); ++c) file.attach_scale(columns[c].name, "t", 0);
    file.commit();
  } catch (const Hdf5Error& e) {
    throw HistoryFileError(e.what());
  }
}

}  // namespace

std::vector<HistoryColumn> history_columns(const Simulation& simulation, const ContactTrace& trace,
                                           const ModelReference* model_reference) {
  return std::visit(
      Overloaded{[&](const RodScene& rod) { return rod_history_columns(rod, trace); },
                 [&](const Scene& bodies) {
                   return bodies_history_columns(bodies, trace, derive(bodies).time_step,
                                                 reference_options(simulation));
                 },
                 [&](const ModelScene& model) {
                   if (!model_reference) {
                     throw HistoryFileError("a model's history needs its reference");
                   }
                   return model_history_columns(model, trace, *model_reference);
                 }},
      simulation.scene);
}

bool is_history_file(const std::filesystem::path& path) {
  if (path.extension() == ".csv") {
    std::ifstream in(path);
    std::string first;
    return std::getline(in, first) && first.rfind("t[", 0) == 0;
  }
  try {
    const Hdf5Reader file(path, UncheckedFile::quiet);
    return file.has_attribute("/", "method") && !file.has_attribute("/", "format") &&
           file.exists("t");
  } catch (const Hdf5Error&) {
    return false;
  }
}

void write_history(const std::filesystem::path& path, const Simulation& simulation,
                   const ContactTrace& trace, const ModelReference* model_reference) {
  const std::string ext = path.extension().string();
  if (ext != ".csv" && ext != ".h5" && ext != ".hdf5") {
    throw HistoryFileError(path.string() +
                           ": unknown history format (use a .csv, .h5 or .hdf5 extension)");
  }
  // A missing folder is created, for either format (as results files are).
  if (path.has_parent_path()) {
    std::error_code ec;
    std::filesystem::create_directories(path.parent_path(), ec);
    if (ec) throw HistoryFileError(path.parent_path().string() + ": " + ec.message());
  }
  if (simulation.model() && !model_reference) {
    throw HistoryFileError(path.string() + ": a model's history needs its reference");
  }
  const std::vector<Column> columns = history_columns(simulation, trace, model_reference);
  if (ext == ".csv") {
    write_csv(path, columns);
  } else {
    write_hdf5(path, columns, simulation);
  }
}

}  // namespace impactid
