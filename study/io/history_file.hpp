// Time histories of one run for people who want to plot them: every sample t_i = i·Δt of the
// contact node (pressure, velocity, displacement), the energy, and the exact values at the same
// samples; with a far wall (RodScene::far_gap) also its pressure, as a last column far_pressure.
// CSV or HDF5, chosen by the file extension (.csv; .h5 or .hdf5). Written atomically.
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/run/simulation.hpp"
#include "study/plan/simulation_settings.hpp"

namespace impactid {

struct HistoryFileError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// One column of a history: what the file stores under `name` (with its units and description)
/// and what `import impactid`'s run object gives as an array (python/).
struct HistoryColumn {
  std::string name;
  std::string units;
  std::string description;
  std::vector<double> values;
};

/// The columns write_history() writes, in file order; t first. A user's model needs its
/// reference, as below; throws HistoryFileError without it.
std::vector<HistoryColumn> history_columns(const Simulation& simulation, const ContactTrace& trace,
                                           const ModelReference* model_reference = nullptr);

/// Whether `path` is a time-history file write_history() wrote (a .csv whose header starts with
/// t[…], or an HDF5 file with the root attribute `method`, no `format`, and the dataset t): one
/// that may be replaced by another run's histories without asking.
bool is_history_file(const std::filesystem::path& path);

/// Throws HistoryFileError (unknown extension, cannot write) naming the file. HDF5 files carry
/// the method and every numeric parameter of the simulation as root attributes. A user's model
/// needs its reference (the one evaluate() used: SimulationWorkspace::model_reference).
void write_history(const std::filesystem::path& path, const Simulation& simulation,
                   const ContactTrace& trace, const ModelReference* model_reference = nullptr);

}  // namespace impactid
