#include "core/reference/chain_exact.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>
#include <stdexcept>
#include <string>

namespace impactid {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// A boundary point of the characteristics: one end of a segment, or the weld of two.
struct Point {
  int left_segment = -1;   // the segment ending here; −1 at a body's first node
  int right_segment = -1;  // the segment starting here; −1 at a body's last node
  int contact = -1;        // the contact acting on this node; −1 for a junction or a free end
  double r_in = 0.0;       // r arriving through the left segment
  double l_in = 0.0;       // l arriving through the right segment
  double l_out = 0.0;      // l emitted into the left segment
  double r_out = 0.0;      // r emitted into the right segment
  double velocity = 0.0;
  double displacement = 0.0;  // at time `since`; the node moves at `velocity` after it
  double since = 0.0;
};

struct ContactState {
  int left_point = -1;   // −1: the left wall
  int right_point = -1;  // −1: the right wall
  int node = -1;         // the node whose velocity and displacement are reported
  bool on_wall = false;
  double wall_position = 0.0;  // the node's displacement while it rests on the wall
  bool closed = false;
  // While open: the gap at gap_time, shrinking at `approach` (the free ends' closing speed), and
  // the closing time that follows (+inf if it does not close).
  double gap = 0.0;
  double gap_time = 0.0;
  double approach = 0.0;
  double closing_time = kInf;
  long version = 0;  // a gap_closes event of an older version is stale
};

enum class EventKind { arrival_from_left, arrival_from_right, gap_closes };

struct Event {
  double time;
  long order;  // ties at equal times go first-in first-out: a deterministic run
  EventKind kind;
  int index;     // the point (arrivals) or the contact (gap_closes)
  double value;  // the arriving wave value
  long version;  // the contact's version (gap_closes)
};

struct Later {
  bool operator()(const Event& a, const Event& b) const {
    return a.time > b.time || (a.time == b.time && a.order > b.order);
  }
};

// The welded junction of segment a (left, incoming r_a) and b (right, incoming l_b): v and N
// continuous. Written with the reflection and transmission coefficients so that equal
// impedances pass the waves through unchanged to the bit (R = 0, T = 1).
struct Scattered {
  double to_left;   // l emitted into a
  double to_right;  // r emitted into b
  double velocity;
  double force;  // N, tension positive
};
Scattered weld(double r_a, double l_b, double z_a, double z_b) {
  const double sum = z_a + z_b;
  const double reflect_a = (z_a - z_b) / sum;  // R_b = −R_a
  const double transmit_ab = 2.0 * z_a / sum;
  const double transmit_ba = 2.0 * z_b / sum;
  const double to_left = reflect_a * r_a + transmit_ba * l_b;
  const double to_right = transmit_ab * r_a - reflect_a * l_b;
  return {to_left, to_right, r_a + to_left, z_a * (to_left - r_a)};
}

// ∫ f(s) ds (or ∫ f(s)² ds) over [from, to] of a piecewise-constant history.
double integral(const std::vector<double>& time, const std::vector<double>& value, double from,
                double to, bool squared) {
  double sum = 0.0;
  const auto first = std::upper_bound(time.begin(), time.end(), from);
  for (std::size_t i = std::max<std::ptrdiff_t>(first - time.begin() - 1, 0); i < time.size();
       ++i) {
    if (time[i] >= to) break;
    const double lo = std::max(time[i], from);
    const double hi = std::min(i + 1 < time.size() ? time[i + 1] : kInf, to);
    if (hi > lo) sum += (hi - lo) * (squared ? value[i] * value[i] : value[i]);
  }
  return sum;
}

}  // namespace

struct ChainExact::Solver {
  ChainExact& out;
  long max_events;
  double time_tolerance;   // [s]
  double value_tolerance;  // [mm/s]
  double force_tolerance;  // [N]
  std::vector<Point> points;
  std::vector<int> segment_left_point, segment_right_point;
  std::vector<ContactState> contacts;
  std::priority_queue<Event, std::vector<Event>, Later> queue;
  long next_order = 0;
  // Points and contacts to solve at the current event time, without duplicates.
  std::vector<int> dirty_points, dirty_contacts;
  std::vector<char> point_is_dirty, contact_is_dirty;

  Solver(ChainExact& result, const Scene& scene, const ChainExactOptions& options)
      : out(result), max_events(options.max_events) {
    double speed = 0.0, impedance = 0.0;
    std::vector<int> first_point, last_point;  // of each body
    for (std::size_t b = 0; b < scene.bodies.size(); ++b) {
      const Body& body = scene.bodies[b];
      speed = std::max(speed, std::abs(body.velocity));
      const int first = static_cast<int>(points.size());
      first_point.push_back(first);
      last_point.push_back(first + static_cast<int>(body.segments.size()));
      for (std::size_t s = 0; s <= body.segments.size(); ++s) {
        Point p;
        p.velocity = body.velocity;
        // Unstressed at v0: r = l = v0/2 on every side.
        p.r_in = p.l_in = p.l_out = p.r_out = 0.5 * body.velocity;
        points.push_back(p);
      }
      for (std::size_t s = 0; s < body.segments.size(); ++s) {
        const Segment& seg = body.segments[s];
        const double c = std::sqrt(seg.youngs_modulus / seg.density);
        SegmentWaves waves{.travel_time = seg.length / c,
                           .impedance = seg.density * c * seg.area,
                           .body = static_cast<int>(b),
                           .right_going = {{-kInf}, {0.5 * body.velocity}},
                           .left_going = {{-kInf}, {0.5 * body.velocity}}};
        impedance = std::max(impedance, waves.impedance);
        const int index = static_cast<int>(out.segments_.size());
        out.segments_.push_back(std::move(waves));
        const int left = first + static_cast<int>(s);
        segment_left_point.push_back(left);
        segment_right_point.push_back(left + 1);
        points[left].right_segment = index;
        points[left + 1].left_segment = index;
      }
    }
    time_tolerance = out.time_tolerance_;
    value_tolerance = options.value_tolerance * speed;
    force_tolerance = value_tolerance * impedance;

    for (const SceneContact& sc : scene_contacts(scene)) {
      ContactState c;
      c.gap = sc.gap;
      if (sc.left_body >= 0) c.left_point = last_point[sc.left_body];
      if (sc.right_body >= 0) c.right_point = first_point[sc.right_body];
      c.node = sc.kind == ContactKind::left_wall ? c.right_point : c.left_point;
      c.on_wall = sc.kind != ContactKind::bodies;
      c.wall_position = sc.kind == ContactKind::left_wall ? -sc.gap : sc.gap;
      const int k = static_cast<int>(contacts.size());
      if (c.left_point >= 0) points[c.left_point].contact = k;
      if (c.right_point >= 0) points[c.right_point].contact = k;
      contacts.push_back(c);
      out.contacts_.push_back(ContactTrace{.area = sc.area,
                                           .time = {0.0},
                                           .force = {0.0},
                                           .velocity = {points[c.node].velocity},
                                           .displacement = {0.0}});
    }
    point_is_dirty.assign(points.size(), 0);
    contact_is_dirty.assign(contacts.size(), 0);
  }

  void run() {
    // t = 0: contacts at gap 0 close now if their ends approach; the others schedule closing.
    for (std::size_t k = 0; k < contacts.size(); ++k) mark_contact(static_cast<int>(k));
    solve_dirty(0.0);
    const double horizon = out.t_end_ + time_tolerance;
    while (!queue.empty() && queue.top().time <= horizon) {
      const double t = queue.top().time;
      while (!queue.empty() && queue.top().time <= t + time_tolerance) {
        apply(queue.top(), t);
        queue.pop();
      }
      solve_dirty(t);
    }
  }

  void count_event(double t) {
    if (++out.events_ > max_events) {
      throw std::runtime_error(
          "ChainExact: more than " + std::to_string(max_events) +
          " events by t = " + format_value(t) + " s (t_end = " + format_value(out.t_end_) +
          " s): the scene's junctions split wave fronts faster than the cap allows; shorten "
          "t_end or raise ChainExactOptions::max_events");
    }
  }

  void apply(const Event& e, double t) {
    switch (e.kind) {
      case EventKind::arrival_from_left:
        count_event(t);
        points[e.index].r_in = e.value;
        mark_point(e.index);
        break;
      case EventKind::arrival_from_right:
        count_event(t);
        points[e.index].l_in = e.value;
        mark_point(e.index);
        break;
      case EventKind::gap_closes:
        if (e.version != contacts[e.index].version) return;  // the approach changed since
        count_event(t);
        contacts[e.index].gap = 0.0;
        contacts[e.index].gap_time = t;
        mark_contact(e.index);
        break;
    }
  }

  void mark_point(int p) {
    if (points[p].contact >= 0) {
      mark_contact(points[p].contact);
    } else if (!point_is_dirty[p]) {
      point_is_dirty[p] = 1;
      dirty_points.push_back(p);
    }
  }
  void mark_contact(int k) {
    if (!contact_is_dirty[k]) {
      contact_is_dirty[k] = 1;
      dirty_contacts.push_back(k);
    }
  }

  // Every solve reads only incoming values and emits into the future (t + L/c), so the order of
  // the solves within one event time does not matter.
  void solve_dirty(double t) {
    for (const int p : dirty_points) {
      solve_point(p, t);
      point_is_dirty[p] = 0;
    }
    dirty_points.clear();
    for (const int k : dirty_contacts) {
      solve_contact(k, t);
      contact_is_dirty[k] = 0;
    }
    dirty_contacts.clear();
  }

  // A junction inside a body, or a body's end without a contact (a free end).
  void solve_point(int p, double t) {
    Point& point = points[p];
    if (point.left_segment >= 0 && point.right_segment >= 0) {
      const Scattered s = weld(point.r_in, point.l_in, out.segments_[point.left_segment].impedance,
                               out.segments_[point.right_segment].impedance);
      emit_left(p, s.to_left, t);
      emit_right(p, s.to_right, t);
      move(point, s.velocity, t);
    } else if (point.left_segment >= 0) {
      emit_left(p, point.r_in, t);
      move(point, 2.0 * point.r_in, t);
    } else {
      emit_right(p, point.l_in, t);
      move(point, 2.0 * point.l_in, t);
    }
  }

  void solve_contact(int k, double t) {
    ContactState& c = contacts[k];
    Point* left = c.left_point >= 0 ? &points[c.left_point] : nullptr;
    Point* right = c.right_point >= 0 ? &points[c.right_point] : nullptr;
    // The free velocities of the two ends (a wall's is 0).
    const double free_left = left ? 2.0 * left->r_in : 0.0;
    const double free_right = right ? 2.0 * right->l_in : 0.0;
    const double approach = free_left - free_right;

    if (!c.closed) {
      if (c.closing_time <= t + time_tolerance) {
        c.gap = 0.0;  // its closing event is merged into this time
      } else {
        // Clamped: only round-off can take the gap below 0 before its closing time.
        c.gap = std::max(0.0, c.gap - c.approach * (t - c.gap_time));
      }
    }
    // At gap 0 the contact is closed exactly when the welded force is compressive (λ > 0), i.e.
    // when the free ends approach; λ = 0 gives the same motion open or closed.
    c.closed = (c.closed || c.gap == 0.0) && approach > 0.0;

    double force = 0.0;
    if (c.closed && left && right) {
      const Scattered s = weld(left->r_in, right->l_in, out.segments_[left->left_segment].impedance,
                               out.segments_[right->right_segment].impedance);
      force = -s.force;
      emit_left(c.left_point, s.to_left, t);
      emit_right(c.right_point, s.to_right, t);
      move(*left, s.velocity, t);
      move(*right, s.velocity, t);
    } else if (c.closed && left) {  // the right wall
      force = 2.0 * out.segments_[left->left_segment].impedance * left->r_in;
      emit_left(c.left_point, -left->r_in, t);
      move(*left, 0.0, t);
    } else if (c.closed) {  // the left wall
      force = -2.0 * out.segments_[right->right_segment].impedance * right->l_in;
      emit_right(c.right_point, -right->l_in, t);
      move(*right, 0.0, t);
    } else {
      if (left) {
        emit_left(c.left_point, left->r_in, t);
        move(*left, free_left, t);
      }
      if (right) {
        emit_right(c.right_point, right->l_in, t);
        move(*right, free_right, t);
      }
    }
    // On a wall the node's displacement is the wall's position, without the round-off of v0·t.
    if (c.closed && c.on_wall) points[c.node].displacement = c.wall_position;

    c.gap_time = t;
    if (c.closed) c.gap = 0.0;
    c.approach = approach;
    ++c.version;
    c.closing_time = kInf;
    if (!c.closed && approach > 0.0) {
      c.closing_time = t + c.gap / approach;
      if (c.closing_time <= out.t_end_ + time_tolerance) {
        queue.push({c.closing_time, next_order++, EventKind::gap_closes, k, 0.0, c.version});
      }
    }
    record(k, t, force);
  }

  void record(int k, double t, double force) {
    ContactTrace& trace = out.contacts_[k];
    const Point& node = points[contacts[k].node];
    const bool changed = std::abs(force - trace.force.back()) > force_tolerance ||
                         std::abs(node.velocity - trace.velocity.back()) > value_tolerance;
    if (!changed) return;
    trace.time.push_back(t);
    trace.force.push_back(force);
    trace.velocity.push_back(node.velocity);
    trace.displacement.push_back(node.displacement);
  }

  void move(Point& point, double velocity, double t) {
    point.displacement += point.velocity * (t - point.since);
    point.since = t;
    point.velocity = velocity;
  }

  // l emitted by point p into the segment on its left, arriving at that segment's left end.
  void emit_left(int p, double value, double t) {
    Point& point = points[p];
    if (std::abs(value - point.l_out) <= value_tolerance) return;
    point.l_out = value;
    SegmentWaves& seg = out.segments_[point.left_segment];
    seg.left_going.time.push_back(t);
    seg.left_going.value.push_back(value);
    schedule(t + seg.travel_time, EventKind::arrival_from_right,
             segment_left_point[point.left_segment], value);
  }
  // r emitted by point p into the segment on its right, arriving at that segment's right end.
  void emit_right(int p, double value, double t) {
    Point& point = points[p];
    if (std::abs(value - point.r_out) <= value_tolerance) return;
    point.r_out = value;
    SegmentWaves& seg = out.segments_[point.right_segment];
    seg.right_going.time.push_back(t);
    seg.right_going.value.push_back(value);
    schedule(t + seg.travel_time, EventKind::arrival_from_left,
             segment_right_point[point.right_segment], value);
  }
  void schedule(double time, EventKind kind, int point, double value) {
    if (time > out.t_end_ + time_tolerance) return;  // beyond the solve
    queue.push({time, next_order++, kind, point, value, 0});
  }
};

ChainExact::ChainExact(const Scene& scene, double t_end, const ChainExactOptions& options) {
  if (const auto error = validate(scene)) {
    throw std::invalid_argument("ChainExact: scene " + error->field + " = " + error->value + ": " +
                                error->constraint);
  }
  if (!bodies_start_free(scene)) {
    throw std::invalid_argument(
        "ChainExact: the scene has a clamped wall or an initial displacement: its bodies do not "
        "start free and unstrained, as this solution assumes (core/reference/scene_reference.hpp "
        "measures such a scene against its own exact solution or a converged one)");
  }
  if (!(std::isfinite(t_end) && t_end >= 0.0)) {
    throw std::invalid_argument("ChainExact: t_end = " + format_value(t_end) +
                                ": must be finite and >= 0");
  }
  if (!(std::isfinite(options.merge_tolerance) && options.merge_tolerance >= 0.0)) {
    throw std::invalid_argument(
        "ChainExact: merge_tolerance = " + format_value(options.merge_tolerance) +
        ": must be finite and >= 0");
  }
  if (!(std::isfinite(options.value_tolerance) && options.value_tolerance >= 0.0)) {
    throw std::invalid_argument(
        "ChainExact: value_tolerance = " + format_value(options.value_tolerance) +
        ": must be finite and >= 0");
  }
  if (options.max_events < 1) {
    throw std::invalid_argument("ChainExact: max_events = " + std::to_string(options.max_events) +
                                ": must be >= 1");
  }
  t_end_ = t_end;
  time_tolerance_ = options.merge_tolerance * t_end;
  Solver solver(*this, scene, options);
  solver.run();
}

void ChainExact::require_in_time(double t, const char* what) const {
  if (!(t >= -time_tolerance_ && t <= t_end_ + time_tolerance_)) {
    throw std::out_of_range(std::string("ChainExact::") + what + ": t = " + format_value(t) +
                            " s lies outside the solved interval [0, " + format_value(t_end_) +
                            "] s");
  }
}

ContactNodeValues ChainExact::entry_values(const ContactTrace& trace, std::size_t i,
                                           double t) const {
  return {trace.force[i] / trace.area, trace.velocity[i],
          trace.displacement[i] + trace.velocity[i] * (t - trace.time[i])};
}

ContactNodeValues ChainExact::at(int contact, double t, double jump_tolerance) const {
  require_in_time(t, "at");
  const ContactTrace& trace = contacts_.at(contact);
  const std::vector<double>& time = trace.time;
  // The entry in force at t: the last with time <= t (entry 0 starts at t = 0).
  const std::size_t upper = std::upper_bound(time.begin(), time.end(), t) - time.begin();
  const std::size_t i = upper == 0 ? 0 : upper - 1;
  // The nearest jump within the tolerance: entry i's start or entry i + 1's.
  std::size_t jump = 0;  // 0: none (entry 0 is the initial state, not a jump)
  double distance = kInf;
  for (const std::size_t j : {i, i + 1}) {
    if (j >= 1 && j < time.size() && std::abs(t - time[j]) <= jump_tolerance &&
        std::abs(t - time[j]) < distance) {
      jump = j;
      distance = std::abs(t - time[j]);
    }
  }
  if (jump == 0) return entry_values(trace, i, t);
  // Both limits at the jump itself: the displacement is continuous there.
  const ContactNodeValues before = entry_values(trace, jump - 1, time[jump]);
  const ContactNodeValues after = entry_values(trace, jump, time[jump]);
  return {0.5 * (before.pressure + after.pressure), 0.5 * (before.velocity + after.velocity),
          after.displacement};
}

double ChainExact::force(int contact, double t) const {
  require_in_time(t, "force");
  const ContactTrace& trace = contacts_.at(contact);
  const std::size_t upper =
      std::upper_bound(trace.time.begin(), trace.time.end(), t) - trace.time.begin();
  return trace.force[upper == 0 ? 0 : upper - 1];
}

std::span<const double> ChainExact::jumps(int contact) const {
  const std::vector<double>& time = contacts_.at(contact).time;
  return std::span<const double>(time).subspan(1);
}

ChainBalance ChainExact::balance_at(double t) const {
  require_in_time(t, "balance_at");
  return balance_of(t, -1);
}

ChainBalance ChainExact::body_balance_at(int body, double t) const {
  require_in_time(t, "body_balance_at");
  if (body < 0 || body >= (segments_.empty() ? 0 : segments_.back().body + 1)) {
    throw std::out_of_range("ChainExact::body_balance_at: no body " + std::to_string(body));
  }
  return balance_of(t, body);
}

ChainBalance ChainExact::balance_of(double t, int body) const {
  // Over a segment at time t, r(x) was emitted at its left end at t − x/c and l(x) at its right
  // end at t − (L − x)/c; with dx = c·ds, ∫ρA·f dx = Z·∫f ds over the emission window
  // [t − L/c, t].
  ChainBalance sum{0.0, 0.0};
  for (const SegmentWaves& seg : segments_) {
    if (body >= 0 && seg.body != body) continue;
    const double from = t - seg.travel_time;
    const History& r = seg.right_going;
    const History& l = seg.left_going;
    sum.momentum += seg.impedance * (integral(r.time, r.value, from, t, false) +
                                     integral(l.time, l.value, from, t, false));
    sum.energy += seg.impedance * (integral(r.time, r.value, from, t, true) +
                                   integral(l.time, l.value, from, t, true));
  }
  return sum;
}

}  // namespace impactid
