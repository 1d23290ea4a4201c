#include "study/studies/spectral_study.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "core/spectral/amplification.hpp"
#include "study/formats/hdf5_file.hpp"

namespace impactid {
namespace {

int scan_samples(double omega_min, double omega_max) {
  const double decades = std::log10(omega_max / omega_min);
  return std::max(2, static_cast<int>(std::ceil(decades * kStabilityScanSamplesPerDecade)) + 1);
}

// units and long_name (and a definition when there is one) of one dataset.
void describe(Hdf5Writer& file, const std::string& name, const char* units,
              const std::string& long_name, const std::string& definition = "") {
  if (units) file.attribute(name, "units", std::string(units));
  file.attribute(name, "long_name", long_name);
  if (!definition.empty()) file.attribute(name, "definition", definition);
}

void check_size(const std::filesystem::path& path, const char* name, std::size_t size,
                std::size_t expected) {
  if (size != expected) {
    throw Hdf5Error(path.string() + ": not written: " + name + " has " + std::to_string(size) +
                    " values, expected " + std::to_string(expected));
  }
}

}  // namespace

double stability_scan_max_rho(const MethodParams& params, double omega_max) {
  if (!(omega_max > 0.0 && std::isfinite(omega_max))) return std::nan("");
  const double omega_min = std::min(kStabilityScanMinOmega, omega_max);
  if (omega_min == omega_max) return max_spectral_radius(params, omega_max, omega_max, 1);
  return max_spectral_radius(params, omega_min, omega_max, scan_samples(omega_min, omega_max));
}

long stability_map_evaluations(const SpectralStudy& study) {
  const double omega_min = std::min(kStabilityScanMinOmega, study.stability_omega_max);
  const long samples = omega_min == study.stability_omega_max
                           ? 1
                           : scan_samples(omega_min, study.stability_omega_max);
  return static_cast<long>(study.alpha.size() * study.delta.size()) * samples;
}

SpectralResults compute_spectral_study(const SpectralStudy& study, int threads) {
  SpectralResults r;
  r.omega_dt = study.omega_dt;
  r.alpha = study.alpha;
  r.delta = study.delta;
  r.omega_dt_reference = study.omega_dt_reference;
  r.stability_omega_max = study.stability_omega_max;
  r.threads = std::max(1, threads);

  const long methods = static_cast<long>(study.methods.size());
  const long omegas = static_cast<long>(study.omega_dt.size());
  for (const SpectralMethod& m : study.methods) {
    r.method_label.push_back(m.label);
    r.method_name.push_back(to_string(kind_of(m.params)));
    r.rho_inf.push_back(high_frequency_spectral_radius(m.params));
    r.period_error_coefficient.push_back(period_error_coefficient(m.params));
  }
  const auto curves = static_cast<std::size_t>(methods * omegas);
  r.spectral_radius.resize(curves);
  r.damping_ratio.resize(curves);
  r.period_error.resize(curves);
#pragma omp parallel for schedule(static) num_threads(r.threads)
  for (long i = 0; i < methods * omegas; ++i) {
    const SpectralProperties p =
        spectral_properties(study.methods[static_cast<std::size_t>(i / omegas)].params,
                            study.omega_dt[static_cast<std::size_t>(i % omegas)]);
    const auto k = static_cast<std::size_t>(i);
    r.spectral_radius[k] = p.spectral_radius;
    r.damping_ratio[k] = p.damping_ratio;
    r.period_error[k] = p.period_error;
  }

  // One α per task: the δ minimising the period error, then that α's row of the stability map.
  const long alphas = static_cast<long>(study.alpha.size());
  const std::size_t deltas = study.delta.size();
  r.delta_min_period_error_limit.resize(static_cast<std::size_t>(alphas));
  r.delta_min_period_error.resize(static_cast<std::size_t>(alphas));
  r.stable.resize(static_cast<std::size_t>(alphas) * deltas);
  r.max_spectral_radius.resize(static_cast<std::size_t>(alphas) * deltas);
#pragma omp parallel for schedule(dynamic, 1) num_threads(r.threads)
  for (long a = 0; a < alphas; ++a) {
    const auto row = static_cast<std::size_t>(a);
    const double alpha = study.alpha[row];
    r.delta_min_period_error_limit[row] = hht_delta_minimizing_period_error(alpha, std::nullopt);
    r.delta_min_period_error[row] =
        hht_delta_minimizing_period_error(alpha, study.omega_dt_reference);
    const std::vector<StabilityMapPoint> map =
        hht_stability_map({alpha}, study.delta, study.stability_omega_max);
    for (std::size_t d = 0; d < deltas; ++d) {
      r.stable[row * deltas + d] = map[d].stable ? 1 : 0;
      r.max_spectral_radius[row * deltas + d] = map[d].max_rho;
    }
  }
  return r;
}

void write_spectral_results(const std::filesystem::path& path, const SpectralResults& r) {
  const std::size_t m = r.method_label.size(), k = r.omega_dt.size(), a = r.alpha.size(),
                    d = r.delta.size();
  check_size(path, "method_name", r.method_name.size(), m);
  check_size(path, "spectral_radius", r.spectral_radius.size(), m * k);
  check_size(path, "damping_ratio", r.damping_ratio.size(), m * k);
  check_size(path, "period_error", r.period_error.size(), m * k);
  check_size(path, "rho_inf", r.rho_inf.size(), m);
  check_size(path, "period_error_coefficient", r.period_error_coefficient.size(), m);
  check_size(path, "delta_min_period_error_limit", r.delta_min_period_error_limit.size(), a);
  check_size(path, "delta_min_period_error", r.delta_min_period_error.size(), a);
  check_size(path, "stable", r.stable.size(), a * d);
  check_size(path, "max_spectral_radius", r.max_spectral_radius.size(), a * d);

  Hdf5Writer file(path);
  file.attribute("/", "format", std::string(kSpectralFormat));
  file.attribute("/", "impactid_version", r.impactid_version);
  file.attribute("/", "git_revision", r.git_revision);
  file.attribute("/", "plan", r.plan_text);
  file.attribute("/", "plan_name", r.plan_name);
  file.attribute("/", "study_kind", std::string("spectral"));
  file.attribute("/", "threads", r.threads);
  file.attribute("/", "run_wall_time_s", r.wall_time_s);
  file.attribute("/", "date", r.date);
  file.attribute("/", "omega_dt_reference", r.omega_dt_reference);
  file.attribute("/", "stability_omega_max", r.stability_omega_max);
  file.attribute("/", "stability_omega_min",
                 std::min(kStabilityScanMinOmega, r.stability_omega_max));

  // Dimensions: netCDF-4 coordinate variables (a dimension scale named after itself).
  std::vector<long> method_index(m);
  std::iota(method_index.begin(), method_index.end(), 0L);
  file.dataset("omega_dt", r.omega_dt, {k});
  describe(file, "omega_dt", "1",
           "Omega = omega*dt: angular frequency of the mode times the time step");
  file.dataset("method", method_index, {m});
  describe(file, "method", "1", "index of the method (its label: method_label)");
  file.dataset("alpha", r.alpha, {a});
  describe(file, "alpha", "1", "HHT alpha of eq. 14");
  file.dataset("delta", r.delta, {d});
  describe(file, "delta", "1", "HHT delta of eq. 13 (beta = (1+delta)^2/4, gamma = 1/2+delta)");
  for (const char* scale : {"omega_dt", "method", "alpha", "delta"}) {
    file.dimension_scale(scale, scale);
  }

  file.dataset("method_label", r.method_label);
  describe(file, "method_label", nullptr,
           "the method and its parameters as given in the plan (\"hht alpha=-0.3\")");
  file.dataset("method_name", r.method_name);
  describe(file, "method_name", nullptr,
           "the method: cdm, backward-euler, newmark, hht or generalized-alpha");

  const Hdf5Dims curve{m, k};
  file.dataset("spectral_radius", r.spectral_radius, curve);
  describe(file, "spectral_radius", "1", "spectral radius of the amplification matrix",
           "rho(Omega) = max |lambda_i| over the eigenvalues of the amplification matrix on "
           "u'' + omega^2 u = 0 (spurious roots included)");
  file.dataset("damping_ratio", r.damping_ratio, curve);
  describe(file, "damping_ratio", "1", "algorithmic damping ratio",
           "xi = -ln(a^2 + b^2)/(2*atan2(b, a)) of the principal eigenvalue pair a +- ib; NaN "
           "where no eigenvalue is complex");
  file.dataset("period_error", r.period_error, curve);
  describe(file, "period_error", "1", "relative period error (T_numerical - T)/T",
           "Omega/atan2(b, a) - 1 of the principal eigenvalue pair a +- ib; NaN where no "
           "eigenvalue is complex");
  file.dataset("rho_inf", r.rho_inf, {m});
  describe(file, "rho_inf", "1", "high-frequency spectral radius, the limit Omega -> infinity",
           "analytic limit of rho(Omega); +inf for central difference");
  file.dataset("period_error_coefficient", r.period_error_coefficient, {m});
  describe(file, "period_error_coefficient", "1",
           "c of (T_numerical - T)/T = c*Omega^2 + O(Omega^4) as Omega -> 0");

  file.dataset("delta_min_period_error_limit", r.delta_min_period_error_limit, {a});
  describe(file, "delta_min_period_error_limit", "1",
           "HHT delta minimising the period error as Omega -> 0 (eq. 19 predicts -1.5*alpha)",
           "minimiser over delta in [0, 2] of |c(alpha, delta)|, c the period error coefficient");
  file.dataset("delta_min_period_error", r.delta_min_period_error, {a});
  describe(file, "delta_min_period_error", "1",
           "HHT delta minimising the period error at Omega = omega_dt_reference",
           "minimiser over delta in [0, 2] of |(T_numerical - T)/T| at the root attribute "
           "omega_dt_reference");

  const Hdf5Dims map{a, d};
  file.dataset("stable", r.stable, map);
  describe(file, "stable", "1", "HHT stability: 1 stable, 0 unstable",
           "rho(Omega) <= 1 + 1e-9 for every Omega of the scan from stability_omega_min to "
           "stability_omega_max (root attributes), 100 log-spaced samples per decade");
  file.dataset("max_spectral_radius", r.max_spectral_radius, map);
  describe(file, "max_spectral_radius", "1", "HHT: largest spectral radius over the stability scan",
           "max rho(Omega) over the scan of `stable`");

  for (const char* name : {"method_label", "method_name", "rho_inf", "period_error_coefficient"}) {
    file.attach_scale(name, "method", 0);
  }
  for (const char* name : {"spectral_radius", "damping_ratio", "period_error"}) {
    file.attach_scale(name, "method", 0);
    file.attach_scale(name, "omega_dt", 1);
  }
  for (const char* name : {"delta_min_period_error_limit", "delta_min_period_error"}) {
    file.attach_scale(name, "alpha", 0);
  }
  for (const char* name : {"stable", "max_spectral_radius"}) {
    file.attach_scale(name, "alpha", 0);
    file.attach_scale(name, "delta", 1);
  }
  file.commit();
}

bool is_spectral_results_file(const std::filesystem::path& path) {
  try {
    const Hdf5Reader file(path, UncheckedFile::quiet);
    return file.has_attribute("/", "format") && file.attribute_is_text("/", "format") &&
           file.attribute_string("/", "format") == kSpectralFormat;
  } catch (const std::exception&) {
    return false;
  }
}

}  // namespace impactid
