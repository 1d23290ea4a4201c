// impactid: identify the time-stepping method and its parameters for dynamic contact and
// impact problems. Entry point: parses the command line and runs one subcommand.
#include "study/cli/cli_main.hpp"

int main(int argc, char** argv) {
  return impactid::impactid_main(argc, argv);
}
