#include "study/plan/scene_path.hpp"

#include <charconv>
#include <cmath>
#include <string>
#include <vector>

namespace impactid {
namespace {

std::vector<std::string_view> split(std::string_view path) {
  std::vector<std::string_view> parts;
  std::size_t start = 0;
  while (true) {
    const std::size_t dot = path.find('.', start);
    parts.push_back(path.substr(start, dot == std::string_view::npos ? dot : dot - start));
    if (dot == std::string_view::npos) return parts;
    start = dot + 1;
  }
}

// A 1-based position, or nothing.
std::optional<std::size_t> position(std::string_view text) {
  std::size_t k = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), k);
  if (ec != std::errc() || end != text.data() + text.size() || k < 1) return std::nullopt;
  return k;
}

constexpr const char* kDisplacementKeys =
    "is not a key of the body's initial displacement (displacement.left: u at its first node, "
    "displacement.right: at its last)";

// The number a path points at, or an error naming the path.
struct Target {
  double* real = nullptr;
  int* integer = nullptr;
  std::optional<ParameterError> error;
};

Target find(Scene& scene, std::string_view path, const std::string& value) {
  const std::string p(path);
  const auto bad = [&](std::string why) { return Target{.error = ParameterError{p, value, why}}; };
  const std::vector<std::string_view> parts = split(path);
  if (parts[0] == "wall") {
    if (parts.size() == 3 && parts[2] == "kind" && (parts[1] == "left" || parts[1] == "right")) {
      return bad("is a wall's kind, a choice of the scene file ([scene.wall." +
                 std::string(parts[1]) +
                 "] kind = \"contact\" or \"clamped\"), not a number "
                 "to vary or set");
    }
    if (parts.size() != 3 || parts[2] != "gap" || (parts[1] != "left" && parts[1] != "right")) {
      return bad("is not a wall key (wall.left.gap, wall.right.gap)");
    }
    std::optional<Wall>& wall = parts[1] == "left" ? scene.left_wall : scene.right_wall;
    if (!wall)
      return bad("names a wall the scene does not have ([scene.wall." + std::string(parts[1]) +
                 "])");
    return Target{.real = &wall->gap};
  }
  if (parts[0] != "body" || parts.size() < 3) {
    return bad(
        "is not a scene key (body.<name>.<key>, body.<name>.segment.<k>.<key>, "
        "body.<name>.displacement.<left|right>, wall.<left|right>.gap)");
  }
  Body* body = nullptr;
  for (Body& b : scene.bodies) {
    if (b.name == parts[1]) body = &b;
  }
  if (!body) {
    if (const auto k = position(parts[1]); k && *k <= scene.bodies.size()) {
      body = &scene.bodies[*k - 1];
    }
  }
  if (!body) return bad("names no body of the scene (by name, or its position from 1)");
  const bool first = body == &scene.bodies.front();
  if (parts.size() == 3) {
    if (parts[2] == "velocity") return Target{.real = &body->velocity};
    if (parts[2] == "gap") {
      if (first) {
        if (!scene.left_wall)
          return bad("is the gap of the first body: the scene has no left wall");
        return Target{.real = &scene.left_wall->gap};
      }
      return Target{.real = &body->gap};
    }
    if (parts[2] == "displacement") return bad(kDisplacementKeys);
    return bad("is not a body key (velocity, gap, segment.<k>.<key>)");
  }
  if (parts[2] == "displacement") {
    if (parts.size() == 4 && parts[3] == "left") return Target{.real = &body->displacement.left};
    if (parts.size() == 4 && parts[3] == "right") return Target{.real = &body->displacement.right};
    return bad(kDisplacementKeys);
  }
  if (parts[2] != "segment" || parts.size() != 5) {
    return bad("is not a body key (velocity, gap, segment.<k>.<key>)");
  }
  const auto k = position(parts[3]);
  if (!k || *k > body->segments.size()) {
    return bad("names no segment of body " + body->name + " (it has " +
               std::to_string(body->segments.size()) + ", counted from 1)");
  }
  Segment& seg = body->segments[*k - 1];
  const std::string_view key = parts[4];
  if (key == "length") return Target{.real = &seg.length};
  if (key == "elements") return Target{.integer = &seg.elements};
  if (key == "youngs_modulus") return Target{.real = &seg.youngs_modulus};
  if (key == "density") return Target{.real = &seg.density};
  if (key == "area") return Target{.real = &seg.area};
  return bad("is not a segment key (length, elements, youngs_modulus, density, area)");
}

}  // namespace

bool is_scene_path(std::string_view name) {
  return name.starts_with("body.") || name.starts_with("wall.") || name == "primary_contact" ||
         name == "gravity";
}

std::optional<ParameterError> assign_scene_path(Scene& scene, std::string_view path,
                                                const ParameterValue& value) {
  const auto* number = std::get_if<double>(&value);
  const std::string text =
      number ? format_value(*number) : '"' + std::get<std::string>(value) + '"';
  if (path == "primary_contact") {
    if (number) return ParameterError{"primary_contact", text, "must be a contact's name"};
    scene.primary_contact = std::get<std::string>(value);
    return std::nullopt;
  }
  if (path == "gravity") {
    if (!number) return ParameterError{"gravity", text, "must be a number (mm/s^2, along x)"};
    scene.gravity = *number;
    return std::nullopt;
  }
  Target target = find(scene, path, text);
  if (target.error) return target.error;
  if (!number) return ParameterError{std::string(path), text, "must be a number"};
  if (target.integer) {
    if (!(std::isfinite(*number) && *number == std::floor(*number) && std::abs(*number) < 2e9)) {
      return ParameterError{std::string(path), text, "must be an integer below 2e9"};
    }
    *target.integer = static_cast<int>(*number);
  } else {
    *target.real = *number;
  }
  return std::nullopt;
}

const char* scene_path_units(std::string_view path) {
  if (path == "gravity") return "mm/s^2";
  const std::string_view key = path.substr(path.rfind('.') + 1);
  if (key == "velocity") return "mm/s";
  if (key == "gap" || key == "length") return "mm";
  if (path.find(".displacement.") != std::string_view::npos) return "mm";
  if (key == "youngs_modulus") return "MPa";
  if (key == "density") return "t/mm^3";
  if (key == "area") return "mm^2";
  return "1";
}

std::optional<double> scene_path_value(const Scene& scene, std::string_view path) {
  if (path == "gravity") return scene.gravity;
  Scene copy = scene;  // find() hands out pointers into a scene it may change
  const Target target = find(copy, path, "");
  if (target.real) return *target.real;
  if (target.integer) return *target.integer;
  return std::nullopt;
}

}  // namespace impactid
