// The body of the impactid program: parses the command line and runs one subcommand. Shared by
// the plain program (study/cli/main.cpp) and the MPI one (study/cli/main_mpi.cpp), which passes its
// ways of running a sweep and an optimisation's searches.
#pragma once

#include "study/cli/run_command.hpp"

namespace impactid {

/// Returns the process's exit status.
int impactid_main(int argc, char** argv, const Runners& runners = {});

}  // namespace impactid
