// Spectral studies (`kind = "spectral"`): the computation against what it must reproduce (eq. 19,
// the HHT stability boundary δ = −α, closed forms), the HDF5 layout the figure scripts rely on
// (read back with Hdf5Reader), and `impactid run` on plans/spectral.toml.
#include "study/studies/spectral_study.hpp"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>

#include "core/spectral/amplification.hpp"
#include "study/formats/hdf5_file.hpp"
#include "test_files.hpp"

namespace impactid {
namespace {

namespace fs = std::filesystem;

fs::path scratch(const std::string& name) {
  return testing::scratch_path("spectral_study_test", name);
}

struct Output {
  int status;
  std::string text;
};

Output run(const std::string& arguments) {
  const std::string command = std::string(IMPACTID_EXECUTABLE) + " " + arguments + " 2>&1";
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(command.c_str(), "r"), pclose);
  std::string text;
  std::array<char, 4096> buffer;
  while (std::fgets(buffer.data(), buffer.size(), pipe.get())) text += buffer.data();
  const int raw = pclose(pipe.release());
  return {WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, text};
}

std::vector<double> linear(double from, double to, int partitions) {
  std::vector<double> v;
  for (int i = 0; i <= partitions; ++i) v.push_back(from + (to - from) * i / partitions);
  v.back() = to;
  return v;
}

SpectralStudy small_study() {
  SpectralStudy s;
  s.omega_dt = {0.1, 1.0, 10.0};
  s.methods = {{NewmarkParams{.delta = 0.3}, "newmark delta=0.3"},
               {HhtParams{.alpha = -0.3, .delta = 0.45}, "hht alpha=-0.3 delta=0.45"},
               {BackwardEulerParams{}, "backward-euler"},
               {CentralDifferenceParams{}, "cdm"}};
  s.alpha = linear(-0.5, 0.0, 10);
  s.delta = linear(0.0, 1.0, 20);
  s.omega_dt_reference = 1.0;
  s.stability_omega_max = 100.0;
  return s;
}

TEST(SpectralStudy, CurvesAreTheAmplificationFunctions) {
  const SpectralStudy s = small_study();
  const SpectralResults r = compute_spectral_study(s, 2);
  ASSERT_EQ(r.spectral_radius.size(), 12u);
  for (std::size_t m = 0; m < s.methods.size(); ++m) {
    EXPECT_EQ(r.method_label[m], s.methods[m].label);
    for (std::size_t k = 0; k < s.omega_dt.size(); ++k) {
      const SpectralProperties p = spectral_properties(s.methods[m].params, s.omega_dt[k]);
      const std::size_t i = m * s.omega_dt.size() + k;  // [method, omega_dt], row-major
      EXPECT_EQ(r.spectral_radius[i], p.spectral_radius);
      if (p.oscillatory) {
        EXPECT_EQ(r.damping_ratio[i], p.damping_ratio);
        EXPECT_EQ(r.period_error[i], p.period_error);
      } else {
        EXPECT_TRUE(std::isnan(r.damping_ratio[i]));
      }
    }
  }
  EXPECT_EQ(r.method_name, (std::vector<std::string>{"newmark", "hht", "backward-euler", "cdm"}));
  // Closed forms: backward Euler's period-error coefficient is 1/3, central difference's
  // -1/24; HHT's rho_inf for alpha < -1/3 is the spurious root -alpha/(1+alpha).
  EXPECT_NEAR(r.period_error_coefficient[2], 1.0 / 3.0, 1e-10);
  EXPECT_NEAR(r.period_error_coefficient[3], -1.0 / 24.0, 1e-10);
  EXPECT_TRUE(std::isinf(r.rho_inf[3]));
  EXPECT_NEAR(r.rho_inf[1], 0.3 / 0.7, 1e-7);
  // Central difference past Omega = 2 is not oscillatory.
  EXPECT_TRUE(std::isnan(r.damping_ratio[3 * 3 + 2]));
  EXPECT_GT(r.spectral_radius[3 * 3 + 2], 1.0);
}

TEST(SpectralStudy, DeltaMinimisingThePeriodErrorIsEquation19AsOmegaGoesToZero) {
  const SpectralStudy s = small_study();
  const SpectralResults r = compute_spectral_study(s, 1);
  for (std::size_t a = 0; a < s.alpha.size(); ++a) {
    // hht_delta_minimizing_period_error resolves delta to about 4e-6 as Omega -> 0.
    EXPECT_NEAR(r.delta_min_period_error_limit[a], -1.5 * s.alpha[a], 1e-5) << s.alpha[a];
    // At Omega = 1 it moves, but by less than 0.05 (core/spectral/amplification.hpp).
    EXPECT_NEAR(r.delta_min_period_error[a], -1.5 * s.alpha[a], 0.05) << s.alpha[a];
  }
}

TEST(SpectralStudy, StabilityMapIsTheHalfPlaneDeltaAtLeastMinusAlpha) {
  const SpectralStudy s = small_study();
  const SpectralResults r = compute_spectral_study(s, 2);
  const double cell = s.delta[1] - s.delta[0];
  int stable = 0, unstable = 0;
  for (std::size_t a = 0; a < s.alpha.size(); ++a) {
    for (std::size_t d = 0; d < s.delta.size(); ++d) {
      const double alpha = s.alpha[a], delta = s.delta[d];
      const int flag = r.stable[a * s.delta.size() + d];
      const double rho = r.max_spectral_radius[a * s.delta.size() + d];
      EXPECT_EQ(flag == 1, rho <= 1.0 + kStabilityTolerance);
      if (std::abs(delta + alpha) <= cell) continue;  // within one cell of the boundary
      EXPECT_EQ(flag, delta > -alpha ? 1 : 0) << "alpha " << alpha << " delta " << delta;
      (flag ? stable : unstable)++;
    }
  }
  EXPECT_GT(stable, 50);
  EXPECT_GT(unstable, 10);
}

TEST(SpectralStudy, NumbersDoNotDependOnTheThreadCount) {
  const SpectralStudy s = small_study();
  const SpectralResults one = compute_spectral_study(s, 1), two = compute_spectral_study(s, 2);
  EXPECT_EQ(one.stable, two.stable);
  EXPECT_EQ(one.max_spectral_radius, two.max_spectral_radius);
  EXPECT_EQ(one.delta_min_period_error, two.delta_min_period_error);
  EXPECT_EQ(one.spectral_radius, two.spectral_radius);
}

// The layout of results/README.md, as the figure scripts read it.
void expect_layout(const fs::path& path, std::size_t methods, std::size_t omegas,
                   std::size_t alphas, std::size_t deltas) {
  const Hdf5Reader f(path);
  EXPECT_EQ(f.attribute_string("/", "format"), "impactid-spectral-1");
  EXPECT_EQ(f.attribute_string("/", "study_kind"), "spectral");
  for (const char* a : {"impactid_version", "git_revision", "plan", "plan_name", "date"}) {
    EXPECT_TRUE(f.attribute_is_text("/", a)) << a;
  }
  EXPECT_GT(f.attribute_double("/", "omega_dt_reference"), 0.0);
  EXPECT_GT(f.attribute_double("/", "stability_omega_max"), 0.0);

  const struct {
    const char* name;
    Hdf5Dims shape;
    std::vector<const char*> scales;
  } datasets[] = {
      {"omega_dt", {omegas}, {}},
      {"method", {methods}, {}},
      {"alpha", {alphas}, {}},
      {"delta", {deltas}, {}},
      {"method_label", {methods}, {"method"}},
      {"spectral_radius", {methods, omegas}, {"method", "omega_dt"}},
      {"damping_ratio", {methods, omegas}, {"method", "omega_dt"}},
      {"period_error", {methods, omegas}, {"method", "omega_dt"}},
      {"rho_inf", {methods}, {"method"}},
      {"period_error_coefficient", {methods}, {"method"}},
      {"delta_min_period_error_limit", {alphas}, {"alpha"}},
      {"delta_min_period_error", {alphas}, {"alpha"}},
      {"stable", {alphas, deltas}, {"alpha", "delta"}},
      {"max_spectral_radius", {alphas, deltas}, {"alpha", "delta"}},
  };
  for (const auto& d : datasets) {
    SCOPED_TRACE(d.name);
    ASSERT_TRUE(f.exists(d.name));
    EXPECT_EQ(f.shape(d.name), d.shape);
    EXPECT_TRUE(f.has_attribute(d.name, "long_name"));
    if (std::string(d.name) != "method_label") {
      EXPECT_EQ(f.attribute_string(d.name, "units"), "1");
    }
    if (d.scales.empty()) {
      EXPECT_TRUE(f.is_dimension_scale(d.name));
    }
    for (unsigned i = 0; i < d.scales.size(); ++i) {
      std::string scale = "/";  // appended rather than "/" + …: GCC 12 warns falsely (-Wrestrict)
      scale += d.scales[i];
      EXPECT_EQ(f.attached_scales(d.name, i), std::vector<std::string>{scale});
    }
  }
  EXPECT_EQ(f.longs("method").back(), static_cast<long>(methods) - 1);
}

TEST(SpectralStudy, FileLayoutReadsBack) {
  const SpectralStudy s = small_study();
  SpectralResults r = compute_spectral_study(s, 2);
  r.plan_name = "small";
  r.plan_text = "plan text";
  const fs::path path = scratch("small.h5");
  write_spectral_results(path, r);
  expect_layout(path, 4, 3, 11, 21);
  EXPECT_TRUE(is_spectral_results_file(path));
  const Hdf5Reader f(path);
  EXPECT_EQ(f.strings("method_label"), r.method_label);
  EXPECT_EQ(f.doubles("omega_dt"), s.omega_dt);
  EXPECT_EQ(f.ints("stable"), r.stable);
  EXPECT_EQ(f.doubles("max_spectral_radius"), r.max_spectral_radius);
  EXPECT_EQ(f.doubles("delta_min_period_error_limit"), r.delta_min_period_error_limit);
  EXPECT_EQ(f.attribute_string("/", "plan"), "plan text");
  EXPECT_EQ(f.attribute_double("/", "stability_omega_max"), 100.0);

  SpectralResults broken = r;
  broken.stable.pop_back();
  EXPECT_THROW(write_spectral_results(scratch("broken.h5"), broken), Hdf5Error);
  EXPECT_FALSE(fs::exists(scratch("broken.h5")));
}

// ---- impactid run ---------------------------------------------------------------------------

TEST(SpectralStudyRun, ShippedPlanWritesTheLayout) {
  const fs::path plan = fs::path(IMPACTID_SOURCE_DIR) / "plans/spectral.toml";
  const fs::path out = scratch("spectral.h5");
  const Output dry = run("run " + plan.string() + " --dry-run --output " + out.string());
  ASSERT_EQ(dry.status, 0) << dry.text;
  EXPECT_NE(dry.text.find("method      hht alpha=-0.3 delta=0.45"), std::string::npos) << dry.text;
  EXPECT_NE(dry.text.find("stability map"), std::string::npos) << dry.text;
  EXPECT_FALSE(fs::exists(out));

  const Output o = run("run " + plan.string() + " --output " + out.string());
  ASSERT_EQ(o.status, 0) << o.text;
  expect_layout(out, 6, 201, 21, 41);
  const Hdf5Reader f(out);
  EXPECT_EQ(f.attribute_string("/", "plan_name"), "spectral");
  EXPECT_EQ(
      f.strings("method_label"),
      (std::vector<std::string>{"newmark delta=0.3", "hht alpha=-0.3 delta=0.45", "hht alpha=-0.3",
                                "generalized-alpha rho_inf=0.8", "backward-euler", "cdm"}));
  const std::vector<double> omega = f.doubles("omega_dt");
  EXPECT_EQ(omega.front(), 0.01);
  EXPECT_EQ(omega.back(), 100.0);
  EXPECT_NEAR(omega[100], 1.0, 1e-12);  // log-spaced: the middle of [1e-2, 1e2]

  // --resume recomputes; an existing file of another kind is never overwritten.
  const Output again = run("run " + plan.string() + " --resume --output " + out.string());
  ASSERT_EQ(again.status, 0) << again.text;
  EXPECT_NE(again.text.find("recomputed in full"), std::string::npos) << again.text;
  const fs::path foreign = scratch("foreign.h5");
  std::ofstream(foreign) << "not HDF5";
  const Output refused = run("run " + plan.string() + " --output " + foreign.string());
  EXPECT_EQ(refused.status, 1) << refused.text;
  EXPECT_NE(refused.text.find("left untouched"), std::string::npos) << refused.text;
}

}  // namespace
}  // namespace impactid
