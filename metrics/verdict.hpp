// A run's verdict: what an engineer choosing a method should read from it (issue 34, item 3). A
// run's RunStatus says only whether it finished (`ok`), not whether its answer is usable: a run can
// finish `ok` with a large pressure error and many spurious peaks (the paper's Bathe at Courant 0.5
// does). The verdict adds the indicators, judged against stated thresholds, and whether the
// reference they were measured against can be trusted:
//
//   failed       the run is `failed` (the method could not start, or nothing to measure against)
//   unstable     the run is `unstable` (non-finite values, or the energy grew past its bound)
//   unverified   the run is `ok`, but its reference is not trusted (a converged reference that did
//                not converge, or two reference methods that disagree:
//                core/reference/model_reference.hpp), or a thresholded indicator has no value
//                (NaN): its numbers cannot be judged
//   inaccurate   ε_p > eps_p or ε_v > eps_v (eq. 18), whatever the peaks
//   oscillating  the errors within their thresholds, but NoP_p > nop_p or NoP_v > nop_v
//   accurate     every threshold met
//
// The default thresholds are the shipped practical-range thresholds ε_p <= 0.03 and NoP_p <= 15
// (plans/README.md, "Practical ranges": they reproduce the paper's Newmark stage δ ∈ [0.3, 1]), and
// velocity counterparts chosen the same way, ε_v <= 0.06 and NoP_v <= 15: the velocity's error runs
// well above the pressure's over that stage, so ε_v <= 0.03 would reject most of it
// (docs/conventions.md, "Verdicts", has the measurements).
// The enumerators are in order of severity, the order `impactid compare` sorts by.
//
// Thread safety: values and pure functions.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "core/common/parameter_error.hpp"
#include "core/common/run_record.hpp"
#include "metrics/indicators.hpp"

namespace impactid {

enum class Verdict { accurate, oscillating, inaccurate, unverified, unstable, failed };

/// The one table of names, as the command line, JSON, HDF5 (flag_meanings) and CSV spell them.
const char* to_string(Verdict verdict);
/// The verdict named `name`, or nothing.
std::optional<Verdict> verdict_from_string(std::string_view name);
/// Every verdict, in order of severity (their codes in results files are their indices).
std::span<const Verdict> all_verdicts();

/// The largest values a run may have and still be judged accurate (each inclusive). Each >= 0 and
/// finite; the command line's --verdict-eps-p, … and a plan's [output] verdict_eps_p, ….
struct VerdictThresholds {
  double eps_p = 0.03;  ///< ε_p, eq. 18 for the contact pressure
  double nop_p = 15;    ///< NoP_p, spurious pressure peaks
  double eps_v = 0.06;  ///< ε_v, eq. 18 for the contact-node velocity
  double nop_v = 15;    ///< NoP_v
};

/// The first threshold that is negative, NaN or infinite, as {"verdict_eps_p", value, why}.
std::optional<ParameterError> validate(const VerdictThresholds& thresholds);

/// "eps_p <= 0.03, nop_p <= 15, eps_v <= 0.06, nop_v <= 15" (values in their shortest form).
std::string thresholds_text(const VerdictThresholds& thresholds);

/// The verdict of a run: its status, its indicators (a scene of bodies' or a model's: its primary
/// contact's), whether its reference is trusted (the rod's exact solution always is), and the
/// thresholds. The one place a verdict is decided.
Verdict judge(RunStatus status, const Indicators& indicators, bool reference_trusted,
              const VerdictThresholds& thresholds);

/// `impactid compare`'s order of two runs: by verdict (order of severity), then by eps_p (NaN
/// last); false when neither comes first, so that a stable sort keeps the registry's order.
bool ranks_before(Verdict a, double eps_p_a, Verdict b, double eps_p_b);

/// Why: "eps_p = 0.9032 > 0.03", "nop_p = 115 > 15", "reference not trusted", "all within
/// eps_p <= 0.03, …", or the status; for the text reports.
std::string verdict_reason(RunStatus status, const Indicators& indicators, bool reference_trusted,
                           const VerdictThresholds& thresholds);

}  // namespace impactid
