#include "core/model/scene.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

#include "core/algebra/contact_lcp.hpp"

namespace impactid {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kMax = std::numeric_limits<double>::max();
constexpr double kTiny = std::numeric_limits<double>::min();

double wave_speed(const Segment& s) {
  return std::sqrt(s.youngs_modulus / s.density);
}

// Rigid closing time of a gap that two ends approach at `approach` [mm/s] (+inf if they do not).
double closing_time(double gap, double approach) {
  return approach > 0.0 ? gap / approach : kInf;
}

// The same under a constant acceleration `toward` the wall [mm/s²] (gravity; 0 keeps the line
// above, bit for bit): the first root of gap = approach·t + toward·t²/2, in the form without
// cancellation, 2·gap/(approach + √(approach² + 2·toward·gap)).
double closing_time(double gap, double approach, double toward) {
  if (toward == 0.0) return closing_time(gap, approach);
  if (gap <= 0.0) return approach > 0.0 || (approach == 0.0 && toward > 0.0) ? 0.0 : kInf;
  const double discriminant = approach * approach + 2.0 * toward * gap;
  if (discriminant < 0.0) return kInf;
  const double denominator = approach + std::sqrt(discriminant);
  return denominator > 0.0 ? 2.0 * gap / denominator : kInf;
}

// The speed at which that gap closes (0 if it never does) [mm/s].
double closing_speed(double gap, double approach, double toward) {
  if (!std::isfinite(closing_time(gap, approach, toward))) return 0.0;
  return std::sqrt(std::max(0.0, approach * approach + 2.0 * toward * std::max(0.0, gap)));
}

std::string body_path(const Scene& scene, std::size_t b) {
  const std::string& name = scene.bodies[b].name;
  return "body." + (name.empty() ? std::to_string(b + 1) : name);
}

double body_length(const Body& body) {
  double length = 0.0;
  for (const Segment& s : body.segments) length += s.length;
  return length;
}

// A body's initial strain (right − left)/L; 0 for an undisplaced body.
double initial_strain(const Body& body) {
  if (body.displacement.is_zero()) return 0.0;
  return (body.displacement.right - body.displacement.left) / body_length(body);
}

// The gap still open at t = 0: `gap` less what the initial displacements close of it (`closing`).
// An undisplaced scene's gap is returned as it is, so that its numbers stay those it always had.
double open_gap(double gap, double closing) {
  return closing == 0.0 ? gap : gap - closing;
}

// Appended piece by piece: GCC 12 warns falsely (-Wrestrict) on "[" + std::string.
std::string displacement_text(const LinearDisplacement& d) {
  std::string out = "[";
  out += format_value(d.left);
  out += ", ";
  out += format_value(d.right);
  out += "]";
  return out;
}

bool clamped(const std::optional<Wall>& wall) {
  return wall && wall->kind == WallKind::clamped;
}

bool valid_name(const std::string& name) {
  return !name.empty() && std::all_of(name.begin(), name.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
  });
}

// Under gravity: the continuum's potential energy at t = 0, ρ·A·|g|·∫ (height − u·sign g) over
// every segment (linear in x on a segment, so its midpoint's value times its length), and the
// speed at which a body strikes the wall it falls toward, added to the velocity scale.
void add_gravity(const Scene& s, SceneDerived& d);

}  // namespace

Scene to_scene(const RodScene& rod) {
  Scene scene;
  Body body;
  body.name = "rod";
  body.velocity = rod.velocity;
  body.segments.push_back(Segment{.length = rod.length,
                                  .elements = rod.elements,
                                  .youngs_modulus = rod.youngs_modulus,
                                  .density = rod.density,
                                  .area = rod.area});
  scene.bodies.push_back(body);
  scene.right_wall = Wall{.gap = rod.gap};
  if (rod.far_gap) scene.left_wall = Wall{.gap = *rod.far_gap};
  scene.mass = rod.mass;
  scene.rayleigh_mass = rod.rayleigh_mass;
  scene.rayleigh_stiffness = rod.rayleigh_stiffness;
  scene.courant = rod.courant;
  scene.dt = rod.dt;
  // The rod's default end time follows the main wall's impact even when the far wall is hit
  // first (RodSceneDerived); stating it keeps the two descriptions one run.
  scene.t_end = derive(rod).end_time;
  scene.primary_contact = "wall_right";
  return scene;
}

const char* to_string(WallKind kind) {
  switch (kind) {
    case WallKind::contact:
      return "contact";
    case WallKind::clamped:
      return "clamped";
  }
  return "unknown";
}

std::optional<WallKind> wall_kind_from_string(const std::string& name) {
  for (const WallKind kind : {WallKind::contact, WallKind::clamped}) {
    if (name == to_string(kind)) return kind;
  }
  return std::nullopt;
}

bool bodies_start_free(const Scene& scene) {
  if (clamped(scene.left_wall) || clamped(scene.right_wall)) return false;
  if (scene.gravity != 0.0) return false;
  return std::all_of(scene.bodies.begin(), scene.bodies.end(),
                     [](const Body& body) { return body.displacement.is_zero(); });
}

bool in_paper_form(const Scene& scene) {
  return scene.bodies.size() == 1 && scene.bodies[0].segments.size() == 1 && !scene.left_wall &&
         scene.right_wall && scene.right_wall->kind == WallKind::contact &&
         bodies_start_free(scene);
}

std::optional<RodScene> as_rod(const Scene& scene) {
  if (!in_paper_form(scene)) return std::nullopt;
  const Body& body = scene.bodies[0];
  const Segment& segment = body.segments[0];
  RodScene rod;
  rod.length = segment.length;
  rod.elements = segment.elements;
  rod.youngs_modulus = segment.youngs_modulus;
  rod.density = segment.density;
  rod.area = segment.area;
  rod.velocity = body.velocity;
  rod.gap = scene.right_wall->gap;
  rod.mass = scene.mass;
  rod.rayleigh_mass = scene.rayleigh_mass;
  rod.rayleigh_stiffness = scene.rayleigh_stiffness;
  rod.courant = scene.courant;
  rod.dt = scene.dt;
  rod.t_end = derive(scene).end_time;
  return rod;
}

double transit_time(const Body& body) {
  double t = 0.0;
  for (const Segment& s : body.segments) t += 2.0 * s.length / wave_speed(s);
  return t;
}

std::vector<long> body_first_nodes(const Scene& scene) {
  std::vector<long> first{0};
  for (const Body& body : scene.bodies) {
    long elements = 0;
    for (const Segment& s : body.segments) elements += s.elements;
    first.push_back(first.back() + elements + 1);
  }
  return first;
}

std::vector<double> body_positions(const Scene& scene) {
  std::vector<double> x;
  double at = scene.left_wall ? scene.left_wall->gap : 0.0;
  for (const Body& body : scene.bodies) {
    if (!x.empty()) at += body.gap;
    x.push_back(at);
    at += body_length(body);
  }
  x.push_back(scene.right_wall ? at + scene.right_wall->gap : at);
  return x;
}

double height_above_wall(const Scene& scene, const std::vector<double>& positions, double x) {
  return scene.gravity < 0.0 ? x : positions.back() - x;
}

std::vector<SceneContact> scene_contacts(const Scene& scene) {
  std::vector<SceneContact> contacts;
  const auto& bodies = scene.bodies;
  if (bodies.empty()) return contacts;
  // A gap closes as the constraint's g = u_plus − u_minus − gap rises to 0: an initial
  // displacement of the plus side closes it, of the minus side opens it.
  if (scene.left_wall && scene.left_wall->kind == WallKind::contact) {
    const Body& first = bodies.front();
    contacts.push_back({"wall_left", ContactKind::left_wall, -1, 0, scene.left_wall->gap,
                        first.segments.empty() ? 1.0 : first.segments.front().area,
                        closing_time(open_gap(scene.left_wall->gap, -first.displacement.left),
                                     -first.velocity, -scene.gravity)});
  }
  for (std::size_t b = 0; b + 1 < bodies.size(); ++b) {
    const Body& left = bodies[b];
    const Body& right = bodies[b + 1];
    contacts.push_back(
        {left.name + "-" + right.name, ContactKind::bodies, static_cast<int>(b),
         static_cast<int>(b + 1), right.gap,
         left.segments.empty() ? 1.0 : left.segments.back().area,
         closing_time(open_gap(right.gap, left.displacement.right - right.displacement.left),
                      left.velocity - right.velocity)});
  }
  if (scene.right_wall && scene.right_wall->kind == WallKind::contact) {
    const Body& last = bodies.back();
    contacts.push_back({"wall_right", ContactKind::right_wall, static_cast<int>(bodies.size()) - 1,
                        -1, scene.right_wall->gap,
                        last.segments.empty() ? 1.0 : last.segments.back().area,
                        closing_time(open_gap(scene.right_wall->gap, last.displacement.right),
                                     last.velocity, scene.gravity)});
  }
  return contacts;
}

std::optional<ParameterError> validate(const Scene& s) {
  if (s.bodies.empty()) {
    return ParameterError{"body", "none", "a scene needs at least one body"};
  }
  std::set<std::string> names;
  long nodes = 0;
  for (std::size_t b = 0; b < s.bodies.size(); ++b) {
    const Body& body = s.bodies[b];
    const std::string path = body_path(s, b);
    if (!valid_name(body.name)) {
      return ParameterError{path + ".name", "\"" + body.name + "\"",
                            "must be a non-empty name of letters, digits and '_'"};
    }
    if (!names.insert(body.name).second) {
      return ParameterError{path + ".name", "\"" + body.name + "\"",
                            "is the name of an earlier body: names must be unique"};
    }
    if (body.segments.empty()) {
      return ParameterError{path + ".segment", "none", "a body needs at least one segment"};
    }
    if (auto e = require_in_range("velocity", body.velocity, -kMax, kMax, "must be finite"); e) {
      e->field = path + ".velocity";
      return e;
    }
    if (b == 0 && body.gap != 0.0) {
      return ParameterError{path + ".gap", format_value(body.gap),
                            "must be 0 on the first body: the gap to the left wall is "
                            "wall.left.gap"};
    }
    if (auto e = require_in_range("gap", body.gap, 0.0, kMax,
                                  "must be >= 0 and finite (bodies may not overlap)");
        e) {
      e->field = path + ".gap";
      return e;
    }
    for (std::size_t k = 0; k < body.segments.size(); ++k) {
      const Segment& seg = body.segments[k];
      const std::string at = path + ".segment." + std::to_string(k + 1) + ".";
      if (seg.elements < 1 || seg.elements > 10'000'000) {
        return ParameterError{at + "elements", std::to_string(seg.elements),
                              "must be an integer in [1, 1e7]"};
      }
      nodes += seg.elements;
      for (auto error : {
               require_in_range("length", seg.length, kTiny, kMax, "must be positive and finite"),
               require_in_range("youngs_modulus", seg.youngs_modulus, kTiny, kMax,
                                "must be positive and finite"),
               require_in_range("density", seg.density, kTiny, kMax, "must be positive and finite"),
               require_in_range("area", seg.area, kTiny, kMax, "must be positive and finite"),
           }) {
        if (error) {
          error->field = at + error->field;
          return error;
        }
      }
    }
    if (!(std::isfinite(body.displacement.left) && std::isfinite(body.displacement.right))) {
      return ParameterError{path + ".displacement", displacement_text(body.displacement),
                            "must be finite ([u at the first node, u at the last node], mm)"};
    }
    nodes += 1;
  }
  if (nodes > 10'000'001) {
    return ParameterError{"body", std::to_string(nodes) + " nodes", "must be at most 1e7 nodes"};
  }
  for (const auto& [wall, side] : {std::pair{&s.left_wall, "left"}, {&s.right_wall, "right"}}) {
    if (!*wall) continue;
    const std::string at = std::string("wall.") + side;
    if ((*wall)->kind != WallKind::contact && (*wall)->kind != WallKind::clamped) {
      return ParameterError{at + ".kind", std::to_string(static_cast<int>((*wall)->kind)),
                            "must be \"contact\" or \"clamped\""};
    }
    if (auto e = require_in_range("gap", (*wall)->gap, 0.0, kMax, "must be >= 0 and finite"); e) {
      e->field = at + ".gap";
      return e;
    }
    if ((*wall)->kind != WallKind::clamped) continue;
    if ((*wall)->gap != 0.0) {
      return ParameterError{at + ".gap", format_value((*wall)->gap),
                            "a clamped end has no gap (" + at + ".kind = \"clamped\"): give none"};
    }
    // The clamped node: the first body's first, or the last body's last.
    const bool left = *side == 'l';
    const std::size_t b = left ? 0 : s.bodies.size() - 1;
    const LinearDisplacement& d = s.bodies[b].displacement;
    if ((left ? d.left : d.right) != 0.0) {
      return ParameterError{body_path(s, b) + ".displacement", displacement_text(d),
                            std::string("must be 0 at the clamped end (") + at +
                                ".kind = \"clamped\" holds the body's " +
                                (left ? "first" : "last") + " node at u = 0)"};
    }
  }
  // A modified mass empties each contact node onto its neighbour in the same element
  // (core/model/scene_assembly.hpp): a body needs a node besides its two ends to keep a mass.
  if (has_massless_dofs(s.mass)) {
    for (std::size_t b = 0; b < s.bodies.size(); ++b) {
      int elements = 0;
      for (const Segment& seg : s.bodies[b].segments) elements += seg.elements;
      if (elements < 2) {
        return ParameterError{"mass", to_string(s.mass),
                              "moves each contact node's mass onto its neighbour: " +
                                  body_path(s, b) + " has 1 element, give it at least 2"};
      }
    }
  }
  if (auto e = require_in_range("gravity", s.gravity, -kMax, kMax, "must be finite"); e) return e;
  if (s.gravity != 0.0 && !(s.gravity < 0.0 ? s.left_wall : s.right_wall)) {
    return ParameterError{"gravity", format_value(s.gravity),
                          std::string("points toward the ") + (s.gravity < 0.0 ? "left" : "right") +
                              " end, and the scene has no wall there (wall." +
                              (s.gravity < 0.0 ? "left" : "right") +
                              "): gravity must point toward a wall, the zero of its potential "
                              "energy"};
  }
  for (auto error : {
           require_in_range("rayleigh_mass", s.rayleigh_mass, 0.0, kMax, "must be >= 0 and finite"),
           require_in_range("rayleigh_stiffness", s.rayleigh_stiffness, 0.0, kMax,
                            "must be >= 0 and finite"),
           require_in_range("courant", s.courant, kTiny, kMax, "must be positive and finite"),
       }) {
    if (error) return error;
  }
  if (s.dt && !(std::isfinite(*s.dt) && *s.dt > 0.0)) {
    return ParameterError{"dt", format_value(*s.dt), "must be positive and finite"};
  }
  if (s.t_end && !(std::isfinite(*s.t_end) && *s.t_end > 0.0)) {
    return ParameterError{"t_end", format_value(*s.t_end), "must be positive and finite"};
  }
  const std::vector<SceneContact> contacts = scene_contacts(s);
  if (contacts.size() > static_cast<std::size_t>(kMaxConstraints)) {
    return ParameterError{"body", std::to_string(s.bodies.size()) + " bodies",
                          "give at most " + std::to_string(kMaxConstraints) +
                              " contacts (bodies and walls): the bound of the contact solver"};
  }
  if (contacts.empty()) {
    const bool has_clamp = clamped(s.left_wall) || clamped(s.right_wall);
    return ParameterError{
        "body", s.bodies[0].name,
        std::string("a scene needs at least one contact (a wall or a second body") +
            (has_clamp ? "; a clamped wall is none)" : ")")};
  }
  // The initial displacement must keep every constraint (no contact closed past its gap).
  for (const SceneContact& c : contacts) {
    const Body* left =
        c.left_body >= 0 ? &s.bodies[static_cast<std::size_t>(c.left_body)] : nullptr;
    const Body* right =
        c.right_body >= 0 ? &s.bodies[static_cast<std::size_t>(c.right_body)] : nullptr;
    const double closing =
        (left ? left->displacement.right : 0.0) - (right ? right->displacement.left : 0.0);
    if (closing <= c.gap) continue;
    // Named at the body whose displacement closes it: the left one's if it moves right.
    const bool at_left = left && (!right || left->displacement.right > 0.0);
    const std::size_t b = static_cast<std::size_t>(at_left ? c.left_body : c.right_body);
    return ParameterError{body_path(s, b) + ".displacement",
                          displacement_text(s.bodies[b].displacement),
                          "closes contact " + c.name + " past its gap at t = 0 (it closes " +
                              format_value(closing) + " mm of a " + format_value(c.gap) +
                              " mm gap): an initial state must keep every contact open or "
                              "just closed"};
  }
  if (s.primary_contact) {
    const bool known = std::any_of(contacts.begin(), contacts.end(), [&](const SceneContact& c) {
      return c.name == *s.primary_contact;
    });
    if (!known) {
      std::string names_list;
      for (const SceneContact& c : contacts)
        names_list += (names_list.empty() ? "" : ", ") + c.name;
      return ParameterError{"primary_contact", "\"" + *s.primary_contact + "\"",
                            "is not a contact of the scene (" +
                                (names_list.empty() ? std::string("it has none") : names_list) +
                                ")"};
    }
  }
  const SceneDerived d = derive(s);
  if (auto e = validate_time_grid(s.dt ? "dt" : "courant", s.dt ? *s.dt : s.courant, d.time_step,
                                  d.end_time,
                                  s.t_end ? "" : "the default t_end follows the first contact",
                                  static_cast<int>(contacts.size()))) {
    return e;
  }
  if (d.velocity_scale != 0.0 &&
      !(std::isnormal(d.initial_energy) && std::isnormal(d.velocity_scale * d.velocity_scale))) {
    // Named by what sets the scale: a body's velocity or, failing that, a strained body's
    // displacement.
    std::string field = "velocity";
    if (std::none_of(s.bodies.begin(), s.bodies.end(), [&](const Body& body) {
          return std::abs(body.velocity) == d.velocity_scale;
        })) {
      for (std::size_t b = 0; b < s.bodies.size(); ++b) {
        if (initial_strain(s.bodies[b]) != 0.0) {
          field = body_path(s, b) + ".displacement";
          break;
        }
      }
    }
    return ParameterError{field, format_value(d.velocity_scale),
                          "gives an initial energy of " + format_value(d.initial_energy) +
                              " mJ outside the normal range of double"};
  }
  return std::nullopt;
}

SceneDerived derive(const Scene& s) {
  SceneDerived d{};
  // The step from the segment with the smallest h/c, computed as RodScene computes it
  // (courant·h/c, left to right), so that the one-body shorthand gives the same bits.
  d.min_h_over_c = kInf;
  double step_h = 1.0, step_c = 1.0;
  d.initial_energy = 0.0;
  d.velocity_scale = 0.0;
  d.nodes = 0;
  for (const Body& body : s.bodies) {
    d.nodes += 1;
    d.velocity_scale = std::max(d.velocity_scale, std::abs(body.velocity));
    const double strain = initial_strain(body);
    for (const Segment& seg : body.segments) {
      d.nodes += seg.elements;
      const double c = wave_speed(seg);
      const double h = seg.length / seg.elements;
      if (h / c < d.min_h_over_c) {
        d.min_h_over_c = h / c;
        step_h = h;
        step_c = c;
      }
      d.initial_energy += 0.5 * seg.density * seg.area * seg.length * body.velocity * body.velocity;
      if (strain != 0.0) {  // an unstrained scene's numbers stay those it always had
        d.initial_energy += 0.5 * seg.youngs_modulus * seg.area * seg.length * strain * strain;
        d.velocity_scale = std::max(d.velocity_scale, c * std::abs(strain));
      }
    }
  }
  d.time_step = s.dt ? *s.dt : s.courant * step_h / step_c;
  if (s.gravity != 0.0) add_gravity(s, d);

  const std::vector<SceneContact> contacts = scene_contacts(s);
  d.first_contact_time = kInf;
  int first = -1;
  for (std::size_t k = 0; k < contacts.size(); ++k) {
    if (contacts[k].rigid_closing_time < d.first_contact_time) {
      d.first_contact_time = contacts[k].rigid_closing_time;
      first = static_cast<int>(k);
    }
  }
  d.primary_contact = first < 0 ? 0 : first;
  if (s.primary_contact) {
    for (std::size_t k = 0; k < contacts.size(); ++k) {
      if (contacts[k].name == *s.primary_contact) d.primary_contact = static_cast<int>(k);
    }
  }

  if (s.t_end) {
    d.end_time = *s.t_end;
  } else {
    // The longest transit of a body in the first contact; without a contact, of any body.
    double transit = 0.0;
    for (std::size_t b = 0; b < s.bodies.size(); ++b) {
      const bool involved = first < 0 || contacts[first].left_body == static_cast<int>(b) ||
                            contacts[first].right_body == static_cast<int>(b);
      if (involved) transit = std::max(transit, transit_time(s.bodies[b]));
    }
    const double start = std::isfinite(d.first_contact_time) ? d.first_contact_time : 0.0;
    d.end_time = start + 1.5 * transit;
  }
  d.step_count = step_count(d.end_time, d.time_step);
  return d;
}

namespace {

void add_gravity(const Scene& s, SceneDerived& d) {
  const std::vector<double> x = body_positions(s);
  const double g = std::abs(s.gravity);
  for (std::size_t b = 0; b < s.bodies.size(); ++b) {
    const Body& body = s.bodies[b];
    const double length = body_length(body);
    double start = 0.0;  // x of the segment's first node, from the body's first
    for (const Segment& seg : body.segments) {
      const double mid = start + 0.5 * seg.length;
      const LinearDisplacement& u = body.displacement;
      const double u_mid = u.left + (u.right - u.left) * (mid / length);
      const double height =
          height_above_wall(s, x, x[b] + mid) + (s.gravity < 0.0 ? u_mid : -u_mid);
      d.initial_energy += seg.density * seg.area * seg.length * g * height;
      start += seg.length;
    }
  }
  const SceneContact* wall = nullptr;
  const std::vector<SceneContact> contacts = scene_contacts(s);
  for (const SceneContact& c : contacts) {
    if (c.kind == (s.gravity < 0.0 ? ContactKind::left_wall : ContactKind::right_wall)) wall = &c;
  }
  if (!wall) return;  // a clamp below: nothing falls
  const Body& body = s.gravity < 0.0 ? s.bodies.front() : s.bodies.back();
  const double approach = s.gravity < 0.0 ? -body.velocity : body.velocity;
  const double closing = s.gravity < 0.0 ? -body.displacement.left : body.displacement.right;
  d.velocity_scale =
      std::max(d.velocity_scale, closing_speed(open_gap(wall->gap, closing), approach, g));
}

}  // namespace

}  // namespace impactid
