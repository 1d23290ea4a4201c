// One simulation and its indicators: what `impactid simulate` prints and what every sweep point
// stores. A plan point and `simulate` with the same parameters call this same function, so
// they give identical numbers.
#pragma once

#include "core/simulation.hpp"
#include "metrics/indicators.hpp"
#include "study/simulation_settings.hpp"

namespace impactid {

struct Evaluation {
  RunSummary summary;
  Indicators indicators;
};

Evaluation evaluate(const Simulation& simulation, SimulationWorkspace& workspace);

}  // namespace impactid
