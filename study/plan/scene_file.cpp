#include "study/plan/scene_file.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <vector>

#include "study/plan/toml_reading.hpp"

namespace impactid {
namespace {

using toml_reading::list;
using toml_reading::ordered;

class Reader : public toml_reading::TableReader {
 public:
  using TableReader::TableReader;

  // A segment key of a [[...segment]] table or of a one-segment body; false if not one.
  bool segment_key(Segment& seg, const std::string& key, const toml::node& node,
                   const std::string& path) const {
    if (key == "length")
      seg.length = number(node, path);
    else if (key == "elements")
      seg.elements = integer(node, path);
    else if (key == "youngs_modulus")
      seg.youngs_modulus = number(node, path);
    else if (key == "density")
      seg.density = number(node, path);
    else if (key == "area")
      seg.area = number(node, path);
    else
      return false;
    return true;
  }

  // [u at the first node, u at the last node] (core/model/scene.hpp: LinearDisplacement).
  LinearDisplacement displacement(const toml::node& node, const std::string& path) const {
    const auto* array = node.as_array();
    if (!array || array->size() != 2) {
      fail(node, path,
           "must be an array of two numbers, [u at the body's first node, u at its last] in mm "
           "(linear in between)");
    }
    return {.left = number(*array->get(0), path + "[0]"),
            .right = number(*array->get(1), path + "[1]")};
  }

  Wall wall(const toml::table& t, const std::string& at) const {
    Wall wall;
    for (const auto& [key, value] : ordered(t)) {
      if (key == "gap") {
        wall.gap = number(*value, at + ".gap");
      } else if (key == "kind") {
        const std::string name = string(*value, at + ".kind");
        const std::optional<WallKind> kind = wall_kind_from_string(name);
        if (!kind) {
          fail(*value, at + ".kind",
               "\"" + name +
                   "\" is not a kind of wall (\"contact\": a rigid obstacle, the default; "
                   "\"clamped\": the end node held at u = 0)");
        }
        wall.kind = *kind;
      } else {
        fail(*value, at + "." + key, "unknown key (wall keys: kind, gap)");
      }
    }
    return wall;
  }

  Body body(const toml::table& t, std::size_t index, const std::string& prefix,
            std::optional<double>& first_gap, const toml::node*& first_gap_node) const {
    Body body;
    body.name = "body" + std::to_string(index + 1);
    const std::string at = prefix + ".body." + std::to_string(index + 1) + ".";
    const toml::node* segments = nullptr;
    Segment own;
    const toml::node* own_key = nullptr;
    std::string own_path;
    for (const auto& [key, node] : ordered(t)) {
      const std::string path = at + key;
      if (key == "name") {
        body.name = string(*node, path);
      } else if (key == "velocity") {
        body.velocity = number(*node, path);
      } else if (key == "gap") {
        const double gap = number(*node, path);
        if (index == 0) {
          first_gap = gap;
          first_gap_node = node;
        } else {
          body.gap = gap;
        }
      } else if (key == "displacement") {
        body.displacement = displacement(*node, path);
      } else if (key == "segment") {
        segments = node;
      } else if (segment_key(own, key, *node, path)) {
        if (!own_key) {
          own_key = node;
          own_path = path;
        }
      } else {
        fail(*node, path,
             "unknown key (body keys: name, velocity, gap, displacement, segment, and for a body "
             "of one segment its keys length, elements, youngs_modulus, density, area)");
      }
    }
    if (segments && own_key) {
      fail(*own_key, own_path,
           "a body gives either [[...segment]] tables or one segment's keys itself, not both");
    }
    if (!segments) {
      body.segments.push_back(own);
      return body;
    }
    const auto* array = segments->as_array();
    if (!array || array->empty() || !array->is_array_of_tables()) {
      fail(*segments, at + "segment",
           "must be a non-empty array of tables ([[scene.body.segment]])");
    }
    for (std::size_t k = 0; k < array->size(); ++k) {
      const toml::table& st = *(*array)[k].as_table();
      Segment seg;
      for (const auto& [key, node] : ordered(st)) {
        const std::string path = at + "segment." + std::to_string(k + 1) + "." + key;
        if (!segment_key(seg, key, *node, path)) {
          fail(*node, path,
               "unknown key (segment keys: length, elements, youngs_modulus, density, area)");
        }
      }
      body.segments.push_back(seg);
    }
    return body;
  }
};

}  // namespace

bool is_scene_of_bodies_key(const std::string& key) {
  return key == "body" || key == "wall" || key == "primary_contact" || key == "gravity";
}

bool is_scene_of_bodies(const toml::table& scene) {
  return scene.contains("body") || scene.contains("wall");
}

Scene read_scene_of_bodies(const toml::table& table, const std::string& prefix,
                           const TableFail& fail) {
  const Reader r(fail);
  Scene scene;
  std::optional<double> first_gap;
  const toml::node* first_gap_node = nullptr;
  const toml::node* bodies = table.get("body");
  if (!bodies) {
    r.fail(table, prefix + ".body", "a scene of bodies needs [[" + prefix + ".body]] tables");
  }
  const auto* array = bodies->as_array();
  if (!array || array->empty() || !array->is_array_of_tables()) {
    r.fail(*bodies, prefix + ".body", "must be a non-empty array of tables ([[scene.body]])");
  }
  for (std::size_t b = 0; b < array->size(); ++b) {
    scene.bodies.push_back(r.body(*(*array)[b].as_table(), b, prefix, first_gap, first_gap_node));
  }
  if (const toml::node* walls = table.get("wall")) {
    const toml::table& w = r.table(*walls, prefix + ".wall",
                                   "must be a table ([scene.wall.left], [scene.wall.right])");
    for (const auto& [side, node] : ordered(w)) {
      const std::string at = prefix + ".wall." + side;
      if (side != "left" && side != "right") {
        r.fail(*node, at, "unknown key (walls: left, right)");
      }
      const toml::table& t = r.table(*node, at, "must be a table (kind, gap)");
      (side == "left" ? scene.left_wall : scene.right_wall) = r.wall(t, at);
    }
  }
  if (first_gap) {
    if (!scene.left_wall) {
      r.fail(*first_gap_node, prefix + ".body.1.gap",
             "the first body's gap is to the left wall, and the scene has none ([" + prefix +
                 ".wall.left])");
    }
    if (const auto* t = table.get("wall")->as_table()->get("left")->as_table();
        t && t->contains("gap")) {
      r.fail(*first_gap_node, prefix + ".body.1.gap",
             "the gap to the left wall is given twice (here and in " + prefix + ".wall.left)");
    }
    scene.left_wall->gap = *first_gap;
  }
  if (const toml::node* primary = table.get("primary_contact")) {
    scene.primary_contact = r.string(*primary, prefix + ".primary_contact");
  }
  if (const toml::node* gravity = table.get("gravity")) {
    scene.gravity = r.number(*gravity, prefix + ".gravity");
  }
  std::vector<std::string> names;
  for (const SceneContact& c : scene_contacts(scene)) names.push_back(c.name);
  if (scene.primary_contact &&
      std::find(names.begin(), names.end(), *scene.primary_contact) == names.end()) {
    r.fail(*table.get("primary_contact"), prefix + ".primary_contact",
           "is not a contact of the scene (" + (names.empty() ? "it has none" : list(names)) + ")");
  }
  return scene;
}

}  // namespace impactid
