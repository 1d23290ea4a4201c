// A method written outside the library (issue 35, "the cost of a method is visible"): this file
// alone adds "newmark-twin", Newmark's δ form under another name, through register_method(), and
// runs it through simulate(), a plan's sweep, the references' cache key and the spectral
// analysis, each of which must treat it as they treat Newmark: the same numbers, bit for bit.
// Nothing of the library names it. docs/architecture.md, "A method outside the library".
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <stdexcept>

#include "core/methods/method_families.hpp"
#include "core/methods/method_registry.hpp"
#include "core/run/simulation.hpp"
#include "core/spectral/amplification.hpp"
#include "study/plan/plan.hpp"
#include "study/plan/point_set.hpp"
#include "study/studies/sweep.hpp"

namespace impactid {
namespace {

// ---- The method: what a user writes (its hooks read RegisteredMethodParams::values). ----

constexpr const char* kTwinParameters[] = {"delta"};

double twin_delta(const MethodParams& params) {
  return std::get<RegisteredMethodParams>(params).values[0];
}

MethodParams twin_params(double delta) {
  RegisteredMethodParams p;
  p.values[0] = delta;
  return p;
}

MadeMethod twin_make(const MethodArguments& given) {
  return twin_params(given.number("delta").value_or(0.3));
}

MethodValues twin_values(const MethodParams& params) {
  return {{"delta", twin_delta(params), false}};
}

std::optional<ParameterError> twin_check(const MethodParams& params) {
  return require_in_range("delta", twin_delta(params), 0.0, kFiniteMax, "must be >= 0 and finite");
}

ImplicitCoefficients twin_coefficients(const MethodParams& params) {
  return newmark_family(newmark_from_delta(twin_delta(params)), 0.0, 0.0,
                        ContactWeighting::endpoint);
}

MethodDescriptor twin_method() {
  return {
      .kind = MethodKind::first_registered,  // ignored: register_method() hands the kind out
      .name = "newmark-twin",
      .summary = "Newmark's delta form under another name: a method outside the library",
      .parameters = kTwinParameters,
      .make = twin_make,
      .values = twin_values,
      .choices = no_choices,
      .spectrum = &kSingleStepImplicitSpectrum,
      .same_parameters = same_implicit_coefficients,
      .defaults = [] { return twin_params(0.3); },
      .validate = twin_check,
      .implicit_coefficients = twin_coefficients,
  };
}

// Registered once, before any test reads the registry's new entry.
const MethodKind kTwin = register_method(twin_method());

// ---- The checks. ----

TEST(RegisteredMethod, IsKnownByItsNameAndTakesItsParameters) {
  EXPECT_EQ(kTwin, MethodKind::first_registered);
  EXPECT_EQ(method_kind_from_string("newmark-twin"), kTwin);
  EXPECT_STREQ(to_string(kTwin), "newmark-twin");
  EXPECT_NE(method_names().find("|newmark-twin"), std::string::npos);
  EXPECT_EQ(methods_taking("delta"), "newmark|hht|newmark-twin");

  MethodArguments given;
  given.set("delta", 0.25);
  const auto built = build_method(kTwin, given);
  ASSERT_TRUE(std::holds_alternative<MethodParams>(built));
  const MethodParams& p = std::get<MethodParams>(built);
  EXPECT_EQ(kind_of(p), kTwin);
  EXPECT_EQ(twin_delta(p), 0.25);
  EXPECT_EQ(kind_of(default_params(kTwin)), kTwin);
  EXPECT_TRUE(is_single_step_implicit(p));

  MethodArguments alien;
  alien.set("alpha", -0.1);
  const auto refused = build_method(kTwin, alien);
  ASSERT_TRUE(std::holds_alternative<ParameterError>(refused));
  EXPECT_EQ(std::get<ParameterError>(refused).constraint,
            "is not a parameter of method newmark-twin (it applies to hht)");
  MethodArguments negative;
  negative.set("delta", -1.0);
  EXPECT_EQ(validate(std::get<MethodParams>(build_method(kTwin, negative)))->field, "delta");
}

TEST(RegisteredMethod, RegistrationRefusesWhatTheLibraryCannotRun) {
  MethodDescriptor again = twin_method();
  EXPECT_THROW(register_method(again), std::invalid_argument);  // the name is taken
  MethodDescriptor no_stepper = twin_method();
  no_stepper.name = "newmark-twin-2";
  no_stepper.implicit_coefficients = nullptr;
  try {
    register_method(no_stepper);
    ADD_FAILURE() << "a method without coefficients was registered";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("newmark-twin-2"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(method_kind_from_string("newmark-twin-2"));
}

MethodParams newmark(double delta) {
  MethodArguments given;
  given.set("delta", delta);
  return std::get<MethodParams>(build_method(MethodKind::newmark, given));
}

MethodParams twin(double delta) {
  MethodArguments given;
  given.set("delta", delta);
  return std::get<MethodParams>(build_method(kTwin, given));
}

void expect_same_bits(const std::vector<double>& a, const std::vector<double>& b,
                      const char* what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(double)), 0) << what;
}

// simulate() steps it with the single-step implicit stepper, as Newmark.
TEST(RegisteredMethod, SimulatesAsNewmarkBitForBit) {
  RodScene scene;
  scene.elements = 40;
  RunOptions options;
  options.record_history = true;
  for (const double delta : {0.0, 0.3}) {
    SimulationWorkspace a, b;
    const RunSummary sa = simulate(scene, twin(delta), options, a);
    const RunSummary sb = simulate(scene, newmark(delta), options, b);
    ASSERT_EQ(sa.status, sb.status);
    expect_same_bits(a.trace.pressure, b.trace.pressure, "pressure");
    expect_same_bits(a.trace.velocity, b.trace.velocity, "velocity");
    expect_same_bits(a.trace.energy, b.trace.energy, "energy");
    EXPECT_GT(a.trace.pressure.size(), 100u);
  }
  // The references' cache key tells the two methods apart.
  EXPECT_FALSE(same_method_parameters(twin(0.3), newmark(0.3)));
  EXPECT_TRUE(same_method_parameters(twin(0.3), twin(0.3)));
  EXPECT_FALSE(same_method_parameters(twin(0.3), twin(0.2)));
}

StudyResults sweep(const char* method) {
  const std::string text = std::string(R"(
name = "registered"
[scene]
elements = 40
[method]
name = ")") + method + R"("
[study]
kind = "grid"
[study.axes]
delta = { from = 0.0, to = 1.0, partitions = 20 }
[output]
checkpoint_seconds = 1000.0
)";
  const Plan plan = parse_plan(text, "registered.toml");
  const PointSet points(plan);
  StudyResults results = empty_results(plan, points);
  std::vector<long> all(static_cast<std::size_t>(points.size()));
  for (std::size_t i = 0; i < all.size(); ++i) all[i] = static_cast<long>(i);
  SweepOptions options;
  options.threads = 2;
  const SweepOutcome outcome = run_sweep(points, all, results, options);
  EXPECT_EQ(outcome.computed, points.size());
  return results;
}

// A plan names it; the sweep (batched lanes where the scene allows) gives Newmark's numbers.
TEST(RegisteredMethod, SweepsAsNewmarkBitForBit) {
  const StudyResults a = sweep("newmark-twin"), b = sweep("newmark");
  ASSERT_EQ(a.status, b.status);
  EXPECT_GT(std::count(a.status.begin(), a.status.end(), 0), 10);  // points that ran and are ok
  ASSERT_EQ(a.indicators.size(), b.indicators.size());
  for (std::size_t c = 0; c < a.indicators.size(); ++c) {
    if (a.indicators[c].name == "wall_time_s") continue;
    expect_same_bits(a.indicators[c].values, b.indicators[c].values, a.indicators[c].name.c_str());
  }
}

TEST(RegisteredMethod, HasNewmarksSpectrum) {
  for (const double delta : {0.0, 0.1, 0.5}) {
    EXPECT_EQ(high_frequency_spectral_radius(twin(delta)),
              high_frequency_spectral_radius(newmark(delta)));
    EXPECT_EQ(period_error_coefficient(twin(delta)), period_error_coefficient(newmark(delta)));
    for (const double omega : {0.01, 0.5, 2.0, 100.0}) {
      const SpectralProperties a = spectral_properties(twin(delta), omega);
      const SpectralProperties b = spectral_properties(newmark(delta), omega);
      EXPECT_EQ(a.spectral_radius, b.spectral_radius) << delta << " " << omega;
      EXPECT_EQ(a.period_error, b.period_error) << delta << " " << omega;
    }
  }
  EXPECT_EQ(period_error_coefficient(twin(0.0)), period_error_coefficient(newmark(0.0)));
}

}  // namespace
}  // namespace impactid
