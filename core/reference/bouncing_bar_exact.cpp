#include "core/reference/bouncing_bar_exact.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>
#include <string>

namespace impactid {

namespace {

constexpr double kPeriod = 16.0;  // in τ = t/D
constexpr double kFall = 3.0;     // the first impact, in τ

// One piece of the emitted invariant A(s) = slope·s + offset (in gD) and of its half-integral
// F(s) = f2·s² + f1·s + f0 (in gD²), from `from` to the next piece's `from` (the header's table).
struct Piece {
  double from, slope, offset, f2, f1, f0;
};
constexpr std::array<Piece, 6> kPieces{{
    {-std::numeric_limits<double>::infinity(), 0.0, 0.0, 0.0, 0.0, 0.0},  // rigid fall
    {3.0, 2.0, 0.0, 0.5, 0.0, -4.5},                                      // first contact
    {5.0, 2.0, -4.0, 0.5, -2.0, 5.5},                                     // free, vibrating
    {7.0, 2.0, -8.0, 0.5, -4.0, 19.5},
    {9.0, 2.0, -12.0, 0.5, -6.0, 37.5},
    {11.0, 0.0, 16.0, 0.0, 8.0, -56.0},  // second contact, then the rigid flight
}};

// The two contact episodes of a period, in τ, with the pressure rising (p = τ) or falling
// (p = 16 − τ), in ρgL.
struct PeriodContact {
  double from, to;
  bool rising;
};
constexpr std::array<PeriodContact, 2> kContacts{{{3.0, 5.0, true}, {11.0, 13.0, false}}};

// s mod 16, in [0, 16).
double phase_of(double s) {
  const double r = s - kPeriod * std::floor(s / kPeriod);
  return r >= kPeriod ? r - kPeriod : r;  // round-off can leave exactly 16
}

const Piece& piece_of(double s) {
  std::size_t i = kPieces.size() - 1;
  while (i > 0 && s < kPieces[i].from) --i;
  return kPieces[i];
}

double emitted_at(const Piece& piece, double s) {
  return piece.slope * s + piece.offset;
}

// A(s) for s in [−2, 16]; within `tolerance` of a jump the mean of its one-sided limits.
double emitted(double s, double tolerance) {
  for (std::size_t i = 1; i < kPieces.size(); ++i) {
    const double jump = kPieces[i].from;
    if (std::abs(s - jump) <= tolerance) {
      return 0.5 * (emitted_at(kPieces[i - 1], jump) + emitted_at(kPieces[i], jump));
    }
  }
  return emitted_at(piece_of(s), s);
}

// F(s) = ½∫_{−2}^{s} A for s in [−2, 16]; continuous.
double half_integral(double s) {
  const Piece& p = piece_of(s);
  return (p.f2 * s + p.f1) * s + p.f0;
}

// ∫ p dτ from a contact's start to τ = end (in ρgL·D).
double impulse_until(const PeriodContact& contact, double end) {
  const double squares = 0.5 * (end * end - contact.from * contact.from);
  return contact.rising ? squares : kPeriod * (end - contact.from) - squares;
}

}  // namespace

std::optional<ParameterError> validate(const BouncingBarParams& p) {
  for (auto error : {
           require_positive_finite("length", p.length),
           require_positive_finite("youngs_modulus", p.youngs_modulus),
           require_positive_finite("density", p.density),
           require_positive_finite("gravity", p.gravity),
       }) {
    if (error) return error;
  }
  // The scales of the solution must be numbers too (E/ρ or g·L² can overflow, or underflow to 0).
  const double c = std::sqrt(p.youngs_modulus / p.density);
  const double d = p.length / c;
  const double gap = 0.5 * p.gravity * (kFall * d) * (kFall * d);
  for (const double scale :
       {c, d, p.gravity * d, p.gravity * d * d, p.density * p.gravity * p.length, gap,
        p.density * p.gravity * p.length * (gap + 0.5 * p.length)}) {
    if (!(std::isfinite(scale) && scale > 0.0)) {
      return ParameterError{"youngs_modulus", format_value(p.youngs_modulus),
                            "with density, length and gravity must give positive, finite c, L/c, "
                            "g·L/c, g·(L/c)², ρgL, the drop height and the energy"};
    }
  }
  return std::nullopt;
}

BouncingBarExact::BouncingBarExact(const BouncingBarParams& params) : params_(params) {
  if (const auto error = validate(params)) {
    throw std::invalid_argument("BouncingBarExact: " + error->field + " = " + error->value + ": " +
                                error->constraint);
  }
  speed_ = std::sqrt(params.youngs_modulus / params.density);
  transit_ = params.length / speed_;
  velocity_scale_ = params.gravity * transit_;
  length_scale_ = velocity_scale_ * transit_;
  stress_scale_ = params.density * params.gravity * params.length;
  gap_ = 0.5 * kFall * kFall * length_scale_;
  energy_constant_ = stress_scale_ * (gap_ + 0.5 * params.length);
}

double BouncingBarExact::displacement(double x, double t) const {
  return point(x, t, 0.0).displacement;
}

BarPointValues BouncingBarExact::point(double x, double t, double jump_tolerance) const {
  if (!(x >= 0.0 && x <= params_.length)) {
    throw std::out_of_range("BouncingBarExact: x = " + format_value(x) + " lies outside [0, " +
                            format_value(params_.length) + "]");
  }
  // Reduced to one period first, so that the arguments stay in the table's [−2, 16].
  const double tau = phase_of(t / transit_);
  const double xi = x / params_.length;
  const double tolerance = jump_tolerance / transit_;
  const double up = tau - xi;          // ŵ+ emitted by the lower end
  const double down = tau + xi - 2.0;  // ŵ− reflected by the top
  const double a_up = emitted(up, tolerance), a_down = emitted(down, tolerance);
  return {length_scale_ * (half_integral(up) + half_integral(down) - 0.5 * tau * tau),
          velocity_scale_ * (0.5 * (a_up + a_down) - tau), stress_scale_ * 0.5 * (a_down - a_up)};
}

ContactNodeValues BouncingBarExact::at(double t, double jump_tolerance) const {
  const BarPointValues end = point(0.0, t, jump_tolerance);
  return {-end.stress, end.velocity, end.displacement};
}

bool BouncingBarExact::in_contact(double t) const {
  const double tau = phase_of(t / transit_);
  return std::any_of(kContacts.begin(), kContacts.end(),
                     [&](const PeriodContact& c) { return tau >= c.from && tau <= c.to; });
}

std::vector<ContactEpisode> BouncingBarExact::episodes(double t_end) const {
  constexpr double kMostPeriods = 1e7;
  if (!(std::isfinite(t_end) && t_end >= 0.0 && t_end <= kMostPeriods * period())) {
    throw std::invalid_argument("BouncingBarExact::episodes: t_end = " + format_value(t_end) +
                                ": must be >= 0 and span at most 1e7 periods (" +
                                format_value(kMostPeriods * period()) + ")");
  }
  std::vector<ContactEpisode> result;
  for (long k = 0; kPeriod * k * transit_ <= t_end; ++k) {
    for (const PeriodContact& contact : kContacts) {
      const double start = (kPeriod * k + contact.from) * transit_;
      if (start > t_end) break;
      const double full_end = (kPeriod * k + contact.to) * transit_;
      // The end's phase: the contact's own when complete, else t_end's (clipped to the contact).
      const double end_phase =
          full_end <= t_end ? contact.to
                            : std::clamp(t_end / transit_ - kPeriod * k, contact.from, contact.to);
      result.push_back({start, std::min(full_end, t_end),
                        stress_scale_ * transit_ * impulse_until(contact, end_phase)});
    }
  }
  return result;
}

double BouncingBarExact::energy(double t) const {
  // The field is one quadratic in ξ between the points where τ − ξ or τ + ξ − 2 crosses a jump
  // of A; the two-point Gauss rule is exact there, and its nodes never sit on a jump.
  const double tau = phase_of(t / transit_);
  std::array<double, 2 + 2 * (kPieces.size() - 1)> cuts{};
  std::size_t count = 0;
  cuts[count++] = 0.0;
  cuts[count++] = 1.0;
  for (std::size_t i = 1; i < kPieces.size(); ++i) {
    for (const double xi : {tau - kPieces[i].from, kPieces[i].from + 2.0 - tau}) {
      if (xi > 0.0 && xi < 1.0) cuts[count++] = xi;
    }
  }
  std::sort(cuts.begin(), cuts.begin() + count);
  const double node = 0.5 / std::sqrt(3.0);
  double sum = 0.0;
  for (std::size_t i = 0; i + 1 < count; ++i) {
    const double width = cuts[i + 1] - cuts[i];
    if (width <= 0.0) continue;
    const double mid = 0.5 * (cuts[i] + cuts[i + 1]);
    for (const double xi : {mid - node * width, mid + node * width}) {
      const double x = xi * params_.length;
      const BarPointValues value = point(x, t, 0.0);
      const double density = 0.5 * params_.density * value.velocity * value.velocity +
                             0.5 * value.stress * value.stress / params_.youngs_modulus +
                             params_.density * params_.gravity * (gap_ + x + value.displacement);
      sum += 0.5 * width * density;
    }
  }
  return sum * params_.length;
}

}  // namespace impactid
