#include "study/cli/model_export.hpp"

#include <cstdio>
#include <fstream>
#include <iostream>
#include <stdexcept>

#include "core/model/scene_assembly.hpp"
#include "core/reference/exact_solution.hpp"
#include "core/run/references.hpp"
#include "study/cli/command_line.hpp"

namespace impactid {
namespace {

std::string number(double x) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.17g", x);
  return buffer;
}

// Writes `text` to path atomically (a .tmp file renamed).
void write_file(const std::filesystem::path& path, const std::string& text) {
  std::filesystem::path temporary = path;
  temporary += ".tmp";
  {
    std::ofstream out(temporary, std::ios::binary);
    out << text;
    if (!out) throw std::runtime_error(path.string() + ": cannot write");
  }
  std::filesystem::rename(temporary, path);
}

// A symmetric matrix as Matrix Market coordinate real symmetric (its lower triangle, 1-based).
std::string matrix_market(const Tridiagonal& a, const std::string& what) {
  const Eigen::Index n = a.size();
  std::string body;
  long entries = 0;
  for (Eigen::Index j = 0; j < n; ++j) {
    if (a.diag[j] != 0.0) {
      body += std::to_string(j + 1) + " " + std::to_string(j + 1) + " " + number(a.diag[j]) + "\n";
      ++entries;
    }
    if (j + 1 < n && a.lower[j + 1] != 0.0) {
      body +=
          std::to_string(j + 2) + " " + std::to_string(j + 1) + " " + number(a.lower[j + 1]) + "\n";
      ++entries;
    }
  }
  return "%%MatrixMarket matrix coordinate real symmetric\n% " + what +
         ", written by impactid export-model\n" + std::to_string(n) + " " + std::to_string(n) +
         " " + std::to_string(entries) + "\n" + body;
}

struct ExportedContact {
  std::string name;
  Constraint constraint;
  ContactProbe probe;
};

}  // namespace

void export_model(const Simulation& sim, const std::filesystem::path& directory) {
  if (sim.model()) {
    throw std::runtime_error("the scene is a model already: its files are its export");
  }
  const Scene* bodies = sim.bodies();
  const RodScene* rod = sim.rod();
  // A model of matrices does not step a massless DOF (core/model/rod_scene.hpp): its M would
  // have a zero row that the sparse steppers cannot start from.
  if (rod && has_massless_dofs(rod->mass)) {
    throw std::runtime_error(std::string("mass = ") + to_string(rod->mass) +
                             ": a model of matrices takes no massless DOF yet; export "
                             "lumped|consistent");
  }
  const AssembledScene scene = bodies ? assemble(*bodies) : assemble(*rod);
  const SecondOrderSystem& system = scene.system;
  const double t_end = bodies ? derive(*bodies).end_time : derive(*rod).end_time;

  std::vector<ExportedContact> contacts;
  if (bodies) {
    const std::vector<SceneContact> list = scene_contacts(*bodies);
    for (std::size_t k = 0; k < list.size(); ++k) {
      contacts.push_back({list[k].name,
                          system.constraints.empty()
                              ? Constraint{system.contact_dof, -1, system.gap}
                              : system.constraints[k],
                          scene.probes[k]});
    }
  } else {
    contacts.push_back({"wall", {system.contact_dof, -1, system.gap}, scene.probes.front()});
    if (system.has_far_contact()) {
      contacts.push_back({"far_wall",
                          {-1, system.far_contact_dof, system.far_gap},
                          {scene.probes.front().area, system.far_contact_dof}});
    }
  }

  // The exact solution at the samples, when the scene has one.
  std::vector<ContactSamples> exact;
  if (rod && !rod->far_gap) {
    const RodImpactExact solution(*rod);
    exact.resize(1);
    for (long i = 1; i <= scene.step_count; ++i) {
      const ContactNodeValues e = solution.at_sample(i);
      exact[0].pressure.push_back(e.pressure);
      exact[0].velocity.push_back(e.velocity);
    }
  } else if (bodies && bodies->rayleigh_mass == 0.0 && bodies->rayleigh_stiffness == 0.0 &&
             (bodies_start_free(*bodies) || clamped_bar_params(*bodies) ||
              bouncing_bar_params(*bodies))) {
    // An exact solution (of the chain, the clamped bar or the bouncing bar), never a converged
    // one: a scene without one exports no reference.
    const SceneReference r = scene_reference(*bodies, ReferenceOptions{});
    if (r.usable() && r.refinements == 0) exact = r.contacts;
  }

  std::filesystem::create_directories(directory);
  write_file(directory / "M.mtx", matrix_market(system.mass, "mass matrix M [t]"));
  write_file(directory / "K.mtx", matrix_market(system.stiffness, "stiffness matrix K [N/mm]"));
  const bool damped = system.has_damping();
  if (damped)
    write_file(directory / "C.mtx", matrix_market(system.damping, "damping matrix C [N s/mm]"));

  const Eigen::VectorXd& v0 = scene.initial_velocity;
  const bool uniform = (v0.array() == v0[0]).all();
  if (!uniform) {
    std::string text = "%%MatrixMarket matrix array real general\n% initial velocity [mm/s]\n" +
                       std::to_string(v0.size()) + " 1\n";
    for (Eigen::Index i = 0; i < v0.size(); ++i) text += number(v0[i]) + "\n";
    write_file(directory / "v0.mtx", text);
  }
  // A scene of bodies' initial displacement (Body::displacement), at its DOFs (a clamped node is
  // none: core/model/scene_assembly.hpp).
  const Eigen::VectorXd& u0 = scene.initial_displacement;
  if (u0.size() > 0) {
    std::string text = "%%MatrixMarket matrix array real general\n% initial displacement [mm]\n" +
                       std::to_string(u0.size()) + " 1\n";
    for (Eigen::Index i = 0; i < u0.size(); ++i) text += number(u0[i]) + "\n";
    write_file(directory / "u0.mtx", text);
  }

  // Gravity's load (core/model/constant_load.hpp) at the DOFs, with its potential at rest.
  const ConstantLoad& load = system.load;
  if (load.active()) {
    std::string text = "%%MatrixMarket matrix array real general\n% constant load f [N]\n" +
                       std::to_string(load.force.size()) + " 1\n";
    for (Eigen::Index i = 0; i < load.force.size(); ++i) text += number(load.force[i]) + "\n";
    write_file(directory / "f.mtx", text);
  }

  std::string toml =
      "# A built-in impactid scene exported as a user's model by `impactid export-model`:\n"
      "# M, K" +
      std::string(damped ? ", C" : "") + (load.active() ? ", its load f" : "") +
      " in Matrix Market files, its contacts, and" +
      (exact.empty() ? "" : " its exact solution at the run's samples as the reference") +
      ".\n# DOFs count from 0. Units: N, mm, s, t (tonne).\n[scene]\nkind = \"matrices\"\n"
      "units = \"N, mm, s, t\"\n"
      "dt = " +
      number(scene.dt) + "\nt_end = " + number(t_end) + "\nprimary_contact = \"" +
      contacts[static_cast<std::size_t>(scene.primary)].name +
      "\"\n\n[scene.matrices]\n"
      "mass = \"M.mtx\"\nstiffness = \"K.mtx\"\n" +
      (damped ? "damping = \"C.mtx\"\n" : "") + "\n[scene.initial]\n" +
      (u0.size() > 0 ? "displacement = \"u0.mtx\"\n" : "") + "velocity = " +
      (uniform ? "{ value = " + number(v0[0]) + ", dofs = \"all\" }" : std::string("\"v0.mtx\"")) +
      "\n";
  if (load.active()) {
    toml +=
        "\n[scene.load]\nforce = \"f.mtx\"\npotential_at_rest = " + number(load.rest_potential) +
        "\n";
  }
  for (const ExportedContact& c : contacts) {
    toml += "\n[[scene.contact]]\nname = \"" + c.name + "\"\n";
    if (c.constraint.plus >= 0 && c.constraint.minus >= 0) {
      toml += "dofs = [" + std::to_string(c.constraint.plus) + ", " +
              std::to_string(c.constraint.minus) + "]\n";
    } else if (c.constraint.plus >= 0) {
      toml += "dof = " + std::to_string(c.constraint.plus) + "\nside = \"upper\"\n";
    } else {
      toml += "dof = " + std::to_string(c.constraint.minus) + "\nside = \"lower\"\n";
    }
    toml += "gap = " + number(c.constraint.gap) + "\narea = " + number(c.probe.area) +
            "\nvelocity_dof = " + std::to_string(c.probe.velocity_dof) + "\n";
  }
  if (!exact.empty()) {
    toml += "\n[scene.reference]\nfile = \"reference.csv\"\n";
    std::string csv = "t";
    for (std::size_t k = 0; k < exact.size(); ++k) {
      csv += "," + contacts[k].name + ".pressure," + contacts[k].name + ".velocity";
    }
    csv += "\n";
    for (long i = 1; i <= scene.step_count; ++i) {
      csv += number(static_cast<double>(i) * scene.dt);
      for (const ContactSamples& s : exact) {
        const auto j = static_cast<std::size_t>(i - 1);
        csv += "," + number(s.pressure[j]) + "," + number(s.velocity[j]);
      }
      csv += "\n";
    }
    write_file(directory / "reference.csv", csv);
  }
  write_file(directory / "scene.toml", toml);
}

std::function<int()> add_export_model_command(CLI::App& app) {
  auto* command = app.add_subcommand(
      "export-model",
      "Write a built-in scene as a user's model: Matrix Market M, K (C), a scene file of kind "
      "\"matrices\" and its exact solution as reference");
  struct Options {
    GivenOptions given;
    SceneOptions scene;
    std::string output;
  };
  auto options = std::make_shared<Options>();
  add_parameter_options(*command, options->given, {ParameterGroup::scene});
  add_scene_options(*command, options->scene);
  command->add_option("--output", options->output, "Folder for the files (created if missing)")
      ->required()
      ->type_name("DIR");
  return [command, options]() -> int {
    if (!command->parsed()) return -1;
    SimulationSettings settings;
    if (!apply_scene_options(options->scene, settings, "export-model") ||
        !apply_options(options->given, settings, "export-model")) {
      return kExitBadInput;
    }
    const auto sim = build_or_report(settings, "export-model");
    if (!sim) return kExitBadInput;
    try {
      export_model(*sim, options->output);
    } catch (const std::exception& e) {
      std::cerr << "impactid export-model: " << e.what() << '\n';
      return kExitFailure;
    }
    std::cerr << "impactid export-model: wrote " << options->output
              << "/scene.toml and its files\n";
    return 0;
  };
}

}  // namespace impactid
