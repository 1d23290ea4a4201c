// libFuzzer target: any bytes as the text of a plan file (study/plan/plan.hpp, plans/README.md).
//
// The contract under test: parse_plan() either returns a plan whose every promise holds, or
// throws PlanError. A crash, a sanitizer report, a hang, or an exception of any other type
// (std::out_of_range from a container, toml++'s own error, std::bad_variant_access…) is a
// finding: `impactid run` turns only PlanError into "file:line:column: key = value: what is
// wrong" and exit status 2.
//
// Promises of a returned plan that are checked here, because `impactid run` relies on them
// without checking again (std::get<Simulation>(build(...)) in study/cli/run_command.cpp):
//   - grid and list: every point builds (PointSet::settings "does not fail for a loaded
//     plan"); checked on the first, middle and last point, as --dry-run times them;
//   - optimize: the start point builds (--dry-run times it);
//   - the plan keeps its text, its name is not empty and holds no '/' or '\'.
//
// Run it with scripts/fuzz; seeds: plans/*.toml and fuzz/corpus/plan/, dictionary fuzz/toml.dict.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <typeinfo>
#include <variant>

#include "study/plan/plan.hpp"
#include "study/plan/point_set.hpp"
#include "study/plan/simulation_settings.hpp"

namespace {

[[noreturn]] void finding(const std::string& what) {
  std::fprintf(stderr, "plan_fuzzer: FINDING: %s\n", what.c_str());
  std::abort();  // libFuzzer saves the input as crash-<sha1>
}

void require_builds(const impactid::SimulationSettings& settings, const std::string& where) {
  const auto built = impactid::build(settings);
  if (const auto* error = std::get_if<impactid::ParameterError>(&built)) {
    finding("parse_plan accepted a plan whose " + where + " does not build: " + error->field +
            " = " + error->value + ": " + error->constraint);
  }
}

void check_promises(const impactid::Plan& plan, const std::string& text) {
  using impactid::StudyKind;
  if (plan.text != text) finding("Plan::text is not the text parsed");
  if (plan.name.empty() || plan.name.find_first_of("/\\") != std::string::npos) {
    finding("accepted the plan name '" + plan.name + "'");
  }
  if (plan.kind == StudyKind::grid || plan.kind == StudyKind::list) {
    const impactid::PointSet points(plan);
    if (points.size() < 1) finding("a grid or list plan with no point");
    for (const long index : {0L, points.size() / 2, points.size() - 1}) {
      require_builds(points.settings(index), "point " + std::to_string(index));
    }
  } else if (plan.kind == StudyKind::optimize) {
    impactid::SimulationSettings start = plan.base;
    for (const impactid::OptimizeParameter& p : plan.optimize.parameters) {
      if (const auto error = impactid::assign(start, p.name, p.initial())) {
        finding("optimize parameter " + p.name + " cannot be assigned: " + error->constraint);
      }
    }
    require_builds(start, "optimisation start point");
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  impactid::Plan plan;
  try {
    plan = impactid::parse_plan(text, "fuzz.toml");
  } catch (const impactid::PlanError&) {
    return 0;  // the expected outcome for bad input
  } catch (const std::exception& e) {
    finding(std::string("parse_plan threw ") + typeid(e).name() + " (not PlanError): " + e.what());
  } catch (...) {
    finding("parse_plan threw something that is not a std::exception");
  }
  try {
    check_promises(plan, text);
  } catch (const std::exception& e) {
    finding(std::string("a parsed plan's points threw ") + typeid(e).name() + ": " + e.what());
  }
  return 0;
}
