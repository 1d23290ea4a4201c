// Time histories of one run for people who want to plot them: every sample t_i = i·Δt of the
// contact node (pressure, velocity, displacement), the energy, and the exact values at the same
// samples. CSV or HDF5, chosen by the file extension (.csv; .h5 or .hdf5). Written atomically.
#pragma once

#include <filesystem>
#include <stdexcept>

#include "core/rod_scene.hpp"
#include "core/simulation.hpp"

namespace impactid {

struct HistoryFileError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Throws HistoryFileError (unknown extension, cannot write) naming the file.
void write_history(const std::filesystem::path& path, const RodScene& scene,
                   const ContactTrace& trace, const std::string& method_name);

}  // namespace impactid
