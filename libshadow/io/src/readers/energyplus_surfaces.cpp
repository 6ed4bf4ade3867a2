// SPDX-License-Identifier: GPL-3.0-or-later
// The EnergyPlus reader's surfaces (scene/energyplus_steps.hpp): detailed and simple zone
// surfaces, shading, openings in their base surface's frame, overhangs and fins, all in model
// coordinates (zone origins, relative north, world or relative coordinate systems).
#include "readers/energyplus_steps.hpp"
#include "readers/energyplus_reveals.hpp"

#include "core/input_checks.hpp"
#include "core/polygon_holes.hpp"
#include "exact/face_shape.hpp"
#include "geometry/newell_normal.hpp"
#include "readers/idf_tokenizer.hpp"
#include "readers/json_document.hpp"
#include "readers/obj_reader.hpp"

#include <shadow/input_file.hpp>

#include <glm/common.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <string_view>
#include <utility>


namespace shadow::scene_readers::energyplus {
namespace {

// ---------------------------------------------------------------------------------------------
// Geometry.

/// cos and sin of an angle in degrees, exact at multiples of 90 (no rounding for square plans).
std::pair<double, double> cos_sin_degrees(double degrees) {
  const double turns = std::fmod(degrees, 360.0);
  const double r = turns < 0 ? turns + 360.0 : turns;
  if (r == 0.0) return {1.0, 0.0};
  if (r == 90.0) return {0.0, 1.0};
  if (r == 180.0) return {-1.0, 0.0};
  if (r == 270.0) return {0.0, -1.0};
  const double radians = r * (3.14159265358979323846 / 180.0);
  return {std::cos(radians), std::sin(radians)};
}

/// A point of a frame whose +y is `degrees` clockwise (seen from above) from the outer frame's +y.
glm::dvec3 rotate_clockwise_frame(const glm::dvec3& p, double degrees) {
  const auto [c, s] = cos_sin_degrees(degrees);
  if (s == 0.0 && c == 1.0) return p;
  return {p.x * c + p.y * s, -p.x * s + p.y * c, p.z};
}

}  // namespace

glm::dvec3 Reader::zone_to_model(const glm::dvec3& p, const ZoneFrame& zone) const {
  if (world_) return p;
  const glm::dvec3 r = rotate_clockwise_frame(p, zone.north);
  return {r.x + zone.origin.x, r.y + zone.origin.y, r.z + zone.origin.z};
}

// World (true north) to building coordinates: the building's +y is north_axis_ clockwise from
// true north, so a world point's building coordinates turn the other way.
glm::dvec3 Reader::world_to_model(const glm::dvec3& p) const {
  // (With world coordinates north_axis_ is the Appendix G rotation alone, usually 0: EnergyPlus
  // turns every surface but site shading by it, so site shading turns back by it here.)
  return rotate_clockwise_frame(p, -north_axis_);
}

std::vector<glm::dvec3> Reader::raw_vertices(const Object& o) const {
  if (!o.vertex_problem.empty()) fail(o.vertex_problem_place, o.vertex_problem);
  std::vector<glm::dvec3> out;
  for (std::size_t n = 0; n < o.vertices.size(); ++n) {
    const auto& v = o.vertices[n];
    glm::dvec3 p;
    for (int a = 0; a < 3; ++a) p[a] = required_number(v[a], "coordinate");
    const std::string problem = detail::coordinate_problem(p, "vertex");
    if (!problem.empty()) fail(v[0].place, problem);
    out.push_back(p);
  }
  const Value& count = field(o, "number_of_vertices");
  const std::optional<double> declared = number(count);
  if (declared && (*declared != std::floor(*declared) || *declared < 0))
    fail(count.place, "not a whole number of vertices: " + detail::format_number(*declared));
  // Compared as doubles: a count like 1e150 does not fit an integer (found by fuzz_energyplus).
  if (declared && *declared != static_cast<double>(out.size()))
    fail(count.place, "says " + detail::format_number(*declared) + " vertices, but " +
                          std::to_string(out.size()) + " are given");
  if (out.size() < 3)
    fail(o.place, "a surface needs at least 3 vertices, " + std::to_string(out.size()) + " given");
  if (clockwise_) std::reverse(out.begin(), out.end());
  return out;
}

// EnergyPlus's Vertex(2) of a surface given by n vertices, as an index into raw_vertices's list:
// GetVertices turns a clockwise list around its first vertex, then rotates it so that the
// first vertex given lands at the Starting Vertex Position's place (upper left 1, lower left 2,
// lower right 3, upper right 4; a triangle's upper right counts as upper left). raw_vertices
// reversed a clockwise list whole (its first vertex last).
std::size_t Reader::lower_left_index(std::size_t n) const {
  if (n == 0) return 0;
  const long long c = n < 4 && start_corner_ == 3 ? 0 : start_corner_;
  const long long size = static_cast<long long>(n);
  const auto mod = [&](long long k) { return static_cast<std::size_t>(((k % size) + size) % size); };
  const std::size_t file_index = clockwise_ ? mod(c - 1) : mod(1 - c);
  return clockwise_ ? n - 1 - file_index : file_index;
}

const Reader::ZoneFrame& Reader::zone_of(const Object& o, std::string_view key) const {
  const Value& v = field(o, key);
  const auto it = zone_index_.find(lower(v.text));
  if (it == zone_index_.end())
    fail(v.place, v.text.empty() ? "missing zone name" : "no Zone named \"" + v.text + "\"");
  return zones_[it->second];
}

std::size_t Reader::base_surface(const Object& o, std::string_view key) const {
  const Value& v = field(o, key);
  const auto it = surface_index_.find(lower(v.text));
  if (it == surface_index_.end() || surfaces_[it->second].opening)
    fail(v.place, v.text.empty() ? "missing base surface name" : "no base surface named \"" + v.text + "\"");
  return it->second;
}

namespace {

// Window, Door, GlazedDoor: a rectangle given in its base surface's own coordinates (x along
// the surface to the right seen from outside, z up the surface; origin at its lower left).
/// A planar surface's own coordinates, as EnergyPlus's simple windows and shades use them
/// (MakeRelativeRectangularVertices): x to the right seen from outside, y up the surface, n out;
/// origin at EnergyPlus's Vertex(2) (`lower_left`). x is horizontal, from the azimuth, except on a
/// horizontal surface, whose azimuth EnergyPlus takes from its edge Vertex(2) -> Vertex(3). width
/// and height are EnergyPlus's: the edges Vertex(2) -> Vertex(3) and Vertex(1) -> Vertex(2).
struct SurfaceFrame {
  glm::dvec3 corner, right, up, n;
  double width = 0.0, height = 0.0;
  [[nodiscard]] glm::dvec3 at(double u, double v) const { return corner + u * right + v * up; }
};

std::optional<SurfaceFrame> surface_frame(const std::vector<glm::dvec3>& b, std::size_t lower_left) {
  SurfaceFrame f;
  f.n = geometry::newell_normal(b, b.front());
  const double n_length = std::sqrt(f.n.x * f.n.x + f.n.y * f.n.y + f.n.z * f.n.z);
  if (!(n_length > 0) || lower_left >= b.size()) return std::nullopt;
  f.n /= n_length;
  // Right seen from outside: up x n; for a horizontal surface, along its edge from Vertex(2).
  // Horizontal as EnergyPlus decides it (DetermineAzimuthAndTilt): the unit normal's z within
  // one bit of +-1, a tilt below about 1.5e-8 radians; a tilt above that takes its azimuth from
  // the normal, however small.
  f.right = glm::dvec3(-f.n.y, f.n.x, 0.0);
  const double r = std::sqrt(f.right.x * f.right.x + f.right.y * f.right.y);
  if (!(std::abs(f.n.z) < 1.0 - 1.12e-16) || !(r > 0.0)) {
    const glm::dvec3 edge = b[(lower_left + 1) % b.size()] - b[lower_left];
    const double e = std::sqrt(edge.x * edge.x + edge.y * edge.y);
    if (!(e > 0)) return std::nullopt;
    f.right = glm::dvec3(edge.x / e, edge.y / e, 0.0);
  } else {
    f.right /= r;
  }
  const glm::dvec3& n = f.n;
  const glm::dvec3& x = f.right;
  f.up = glm::dvec3(n.y * x.z - n.z * x.y, n.z * x.x - n.x * x.z, n.x * x.y - n.y * x.x);
  // EnergyPlus's Width |Vertex(3) - Vertex(2)| and Height |Vertex(2) - Vertex(1)| (GetVertices):
  // what its overhangs and fins are sized by.
  f.corner = b[lower_left];
  const auto length = [](const glm::dvec3& d) { return std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z); };
  f.width = length(b[(lower_left + 1) % b.size()] - f.corner);
  f.height = length(f.corner - b[(lower_left + b.size() - 1) % b.size()]);
  return f;
}

}  // namespace

// Window, Door, GlazedDoor: a rectangle given in its base surface's own coordinates.
std::vector<glm::dvec3> Reader::rectangle_in_base(const Object& o, const Surface& base) const {
  const double x = required_number(field(o, "starting_x_coordinate"), "starting X coordinate");
  const double z = required_number(field(o, "starting_z_coordinate"), "starting Z coordinate");
  const Value& length_field = field(o, "length");
  const Value& height_field = field(o, "height");
  const double length = required_number(length_field, "length");
  const double height = required_number(height_field, "height");
  if (!(length > 0)) fail(length_field.place, "the length must be positive");
  if (!(height > 0)) fail(height_field.place, "the height must be positive");
  const std::optional<SurfaceFrame> f = surface_frame(base.vertices, base.lower_left);
  if (!f) fail(o.place, "its base surface has zero area");
  return {f->at(x, z), f->at(x + length, z), f->at(x + length, z + height), f->at(x, z + height)};
}

// Shading:Overhang(:Projection) and Shading:Fin(:Projection): shades drawn from their window or
// door. The angle from the window is 90 for a shade square to it; below 90 it turns toward the
// wall beyond the window's edge (up for an overhang, outward sideways for a fin).
std::vector<std::vector<glm::dvec3>> Reader::window_shades(const Object& o, const Surface& window) const {
  const std::optional<SurfaceFrame> f = surface_frame(window.vertices, window.lower_left);
  if (!f) fail(o.place, "its window or door has zero area");
  const std::string cls = o.spec->name;
  const bool projection = cls.find(":Projection") != std::string::npos;
  auto depth_of = [&](const char* key, double fraction_of) {
    const Value& v = field(o, key);
    const double d = number(v).value_or(0.0) * (projection ? fraction_of : 1.0);
    if (d < 0) fail(v.place, "the depth must not be negative");
    return d;
  };
  auto angle = [&](const char* key) { return cos_sin_degrees(number_or(o, key, 90.0)); };
  std::vector<std::vector<glm::dvec3>> shades;
  if (cls.rfind("Shading:Overhang", 0) == 0) {
    const double depth = depth_of(projection ? "depth_as_fraction_of_window_door_height" : "depth", f->height);
    if (depth == 0) return shades;
    const double rise = number_or(o, "height_above_window_or_door", 0.0);
    const double left = number_or(o, "left_extension_from_window_door_width", 0.0);
    const double right = number_or(o, "right_extension_from_window_door_width", 0.0);
    const auto [c, s] = angle("tilt_angle_from_window_door");
    const glm::dvec3 out = depth * (s * f->n + c * f->up);
    const glm::dvec3 a = f->at(-left, f->height + rise), b = f->at(f->width + right, f->height + rise);
    shades.push_back({a, b, b + out, a + out});
    return shades;
  }
  // Fins: one on each side with a depth.
  for (const bool left_side : {true, false}) {
    const char* side = left_side ? "left" : "right";
    const std::string depth_key = projection ? std::string(side) + "_depth_as_fraction_of_window_door_width"
                                             : std::string(side) + "_depth";
    const double depth = depth_of(depth_key.c_str(), f->width);
    if (depth == 0) continue;
    const double extension = number_or(o, (std::string(side) + "_extension_from_window_door").c_str(), 0.0);
    const double above = number_or(o, (std::string(side) + "_distance_above_top_of_window").c_str(), 0.0);
    const double below = number_or(o, (std::string(side) + "_distance_below_bottom_of_window").c_str(), 0.0);
    const auto [c, s] = angle((std::string(side) + "_tilt_angle_from_window_door").c_str());
    const double x = left_side ? -extension : f->width + extension;
    // Both fins turn the same way about their vertical edges: EnergyPlus gives each the azimuth
    // window - (180 - tilt), so below 90 degrees the left fin leans over the window and the right
    // one away from it (SurfaceGeometry.cc, Shading:Fin).
    const glm::dvec3 out = depth * (s * f->n + c * f->right);
    const glm::dvec3 a = f->at(x, -below), b = f->at(x, f->height + above);
    shades.push_back({a, b, b + out, a + out});
  }
  return shades;
}

// Shading:Site, Shading:Building, Wall:Exterior, Roof, ...: a rectangle from its lower left
// corner, with its outward normal at `azimuth` (clockwise from north) and tilted `tilt` from the
// horizontal (90: vertical; 0: facing up), in the object's own frame; vertices counter-clockwise
// seen from outside (EnergyPlus builds them so, whatever the vertex entry direction).
std::vector<glm::dvec3> Reader::rectangle(const Object& o, double default_tilt, const char* size_key,
                                          double extra_azimuth, const glm::dvec3* start_at) const {
  const double azimuth = required_number(field(o, "azimuth_angle"), "azimuth angle") + extra_azimuth;
  const double tilt = number_or(o, "tilt_angle", default_tilt);
  const glm::dvec3 start = start_at != nullptr ? *start_at
                                               : glm::dvec3(number_or(o, "starting_x_coordinate", 0.0),
                                                            number_or(o, "starting_y_coordinate", 0.0),
                                                            number_or(o, "starting_z_coordinate", 0.0));
  const Value& length_field = field(o, "length");
  const Value& height_field = field(o, size_key);
  const double length = required_number(length_field, "length");
  const double height = required_number(height_field, size_key);
  if (!(length > 0)) fail(length_field.place, "the length must be positive");
  if (!(height > 0)) fail(height_field.place, std::string("the ") + size_key + " must be positive");
  const auto [ca, sa] = cos_sin_degrees(azimuth);
  const auto [ct, st] = cos_sin_degrees(tilt);
  const glm::dvec3 right(-ca, sa, 0.0);        // up x (horizontal normal (sa, ca, 0))
  const glm::dvec3 up(-ct * sa, -ct * ca, st);  // up the slope, perpendicular to right
  auto at = [&](double u, double v) { return start + u * right + v * up; };
  return {at(0, 0), at(length, 0), at(length, height), at(0, height)};
}

// A simple zone surface (zone given) or Shading:Building (none) whose Rectangular Surface
// Coordinate System differs from the Coordinate System: placed as EnergyPlus's
// MakeRectangularVertices places it, then turned into the model frame (by -north_axis_). Its
// corner: relative, through the zone's frame and the building's rotation (north axis and
// Appendix G), in world coordinates too; world, turned by the Appendix G rotation alone. Its
// azimuth (GetRectSurfaces, GetRectDetShdSurfaceData): the building's and the zone's north are
// added only with relative coordinates, the Appendix G rotation always. Where the two systems
// agree, the caller's direct arithmetic gives the same rectangle.
std::vector<glm::dvec3> Reader::crossed_rectangle(const Object& o, double default_tilt, const char* size_key,
                                                  const ZoneFrame* zone) const {
  glm::dvec3 base(number_or(o, "starting_x_coordinate", 0.0), number_or(o, "starting_y_coordinate", 0.0),
                  number_or(o, "starting_z_coordinate", 0.0));
  double turn = appendix_g_;  // the corner's rotation into EnergyPlus's world
  if (!rectangular_world_) {
    turn += building_north_;
    if (zone != nullptr) {
      base = rotate_clockwise_frame(base, zone->north);
      base += zone->origin;
    }
  }
  double azimuth = appendix_g_;
  if (!world_) azimuth += building_north_ + (zone != nullptr ? zone->north : 0.0);
  const glm::dvec3 corner = rotate_clockwise_frame(base, turn - north_axis_);
  return rectangle(o, default_tilt, size_key, azimuth - north_axis_, &corner);
}

// Shading is opaque here: a transmittance schedule (a tree in leaf) is not applied, and said so.
void Reader::warn_transmittance(const Object& o) {
  const Value& schedule = field(o, "transmittance_schedule_name");
  if (schedule.present)
    warnings_.push_back({{file_, schedule.place}, "transmittance schedule \"" + schedule.text +
                                                      "\" not applied: libshadow's shading surfaces are opaque"});
}

namespace {

/// The simple rectangular zone surfaces: type, exposure and EnergyPlus's default tilt.
struct SimpleSurface {
  const char* cls;
  const char* kind;
  int group;  // Surface::Group
  double tilt;
  const char* size_key;
};

const SimpleSurface* simple_surface(const std::string& cls) {
  // Groups as in Reader::Surface::Group: 0 zone (receives), 3 not exposed, 4 dropped (interzone).
  static const SimpleSurface table[] = {
      {"Wall:Exterior", "Wall", 0, 90.0, "height"},       {"Wall:Adiabatic", "Wall", 3, 90.0, "height"},
      {"Wall:Underground", "Wall", 3, 90.0, "height"},    {"Wall:Interzone", "Wall", 4, 90.0, "height"},
      {"Roof", "Roof", 0, 0.0, "width"},                  {"Ceiling:Adiabatic", "Ceiling", 3, 0.0, "width"},
      {"Ceiling:Interzone", "Ceiling", 4, 0.0, "width"},  {"Floor:GroundContact", "Floor", 3, 180.0, "width"},
      {"Floor:Adiabatic", "Floor", 3, 180.0, "width"},    {"Floor:Interzone", "Floor", 4, 180.0, "width"},
  };
  for (const SimpleSurface& s : table)
    if (cls == s.cls) return &s;
  return nullptr;
}

}  // namespace

/// A surface into surfaces_, its name unique ignoring case (as EnergyPlus reads names).
void Reader::add_surface(Surface s) {
  // Vertices computed from lengths and angles (or moved by a zone origin) can leave the range
  // that the exact cut and the engine accept, though every number read was within it.
  for (const glm::dvec3& p : s.vertices) {
    const std::string problem = detail::coordinate_problem(p, "vertex");
    if (!problem.empty()) fail(s.object->place, problem);
  }
  if (s.name.empty()) s.name = s.object->name;
  const std::string key = lower(s.name);
  if (s.name.empty()) fail(s.object->place, "a surface needs a name");
  const auto [it, inserted] = surface_index_.emplace(key, surfaces_.size());
  if (!inserted) {
    const Surface& first = surfaces_[it->second];
    if (first.name != s.name)
      // EnergyPlus upper-cases names: "Wall1" and "WALL1" are one surface to it (and its
      // shading file's column would shade only one of them).
      fail(s.object->place, "a second surface named \"" + s.name + "\": its name differs from \"" + first.name +
                                "\" (at " + first.object->place + ") only by case, and EnergyPlus upper-cases names, "
                                "so the two are the same surface to it (rename one)");
    fail(s.object->place, "a second surface named \"" + s.name + "\" (EnergyPlus names ignore case; the first is at " +
                              first.object->place + ")");
  }
  surfaces_.push_back(std::move(s));
}

/// A detailed zone surface's group from its outside boundary condition and sun exposure.
Reader::Surface::Group Reader::boundary_group(const Object& o) const {
  const Value& boundary = field(o, "outside_boundary_condition");
  const Value& sun = field(o, "sun_exposure");
  if (same_text(boundary.text, "Surface") || same_text(boundary.text, "Zone")) return Surface::Dropped;
  if (same_text(boundary.text, "Outdoors") && !same_text(sun.text, "NoSun")) return Surface::ZoneGroup;
  if (!boundary.present) fail(boundary.place, "missing outside boundary condition");
  return Surface::NotExposed;
}

void Reader::read_base_surfaces() {
  // Base surfaces and detached shading first: openings and zone shading name them.
  for (const Object& o : objects_) {
    const std::string cls = o.spec->name;
    Surface s;
    s.object = &o;
    if (cls == "BuildingSurface:Detailed" || cls == "Wall:Detailed" || cls == "RoofCeiling:Detailed" ||
        cls == "Floor:Detailed") {
      const ZoneFrame& zone = zone_of(o, "zone_name");
      s.zone = zone.name;
      s.group = boundary_group(o);
      if (cls == "BuildingSurface:Detailed") {
        const Value& type = field(o, "surface_type");
        for (const char* t : {"Wall", "Roof", "Floor", "Ceiling"})
          if (same_text(type.text, t)) s.kind = t;
        if (s.kind.empty()) fail(type.place, "expected Wall, Roof, Floor or Ceiling, not \"" + type.text + "\"");
      } else if (cls == "Wall:Detailed") {
        s.kind = "Wall";
      } else if (cls == "Floor:Detailed") {
        s.kind = "Floor";
      } else {
        s.kind = s.group == Surface::ZoneGroup ? "Roof" : "Ceiling";
      }
      s.vertices = raw_vertices(o);
      s.lower_left = lower_left_index(s.vertices.size());
      for (glm::dvec3& p : s.vertices) p = zone_to_model(p, zone);
      add_surface(std::move(s));
    } else if (const SimpleSurface* simple = simple_surface(cls)) {
      const ZoneFrame& zone = zone_of(o, "zone_name");
      s.zone = zone.name;
      s.kind = simple->kind;
      s.group = static_cast<Surface::Group>(simple->group);
      if (rectangular_world_ != world_) {
        s.vertices = crossed_rectangle(o, simple->tilt, simple->size_key, &zone);
      } else {
        s.vertices = rectangle(o, simple->tilt, simple->size_key);
        for (glm::dvec3& p : s.vertices) p = zone_to_model(p, zone);
      }
      add_surface(std::move(s));
    } else if (cls == "Shading:Site:Detailed" || cls == "Shading:Building:Detailed") {
      warn_transmittance(o);
      s.kind = "Shading";
      s.group = cls == "Shading:Site:Detailed" ? Surface::SiteShading : Surface::BuildingShading;
      s.vertices = raw_vertices(o);
      s.lower_left = lower_left_index(s.vertices.size());
      if (s.group == Surface::SiteShading)
        for (glm::dvec3& p : s.vertices) p = world_to_model(p);
      add_surface(std::move(s));
    } else if (cls == "Shading:Site" || cls == "Shading:Building") {
      s.kind = "Shading";
      s.group = cls == "Shading:Site" ? Surface::SiteShading : Surface::BuildingShading;
      if (s.group == Surface::BuildingShading && rectangular_world_ != world_) {
        s.vertices = crossed_rectangle(o, 90.0, "height", nullptr);
      } else {
        s.vertices = rectangle(o, 90.0, "height");
        if (s.group == Surface::SiteShading)
          for (glm::dvec3& p : s.vertices) p = world_to_model(p);
      }
      add_surface(std::move(s));
    }
  }
}

void Reader::read_openings() {
  // Openings and zone shading: in their base surface's zone frame.
  for (const Object& o : objects_) {
    const std::string cls = o.spec->name;
    Surface s;
    s.object = &o;
    if (cls == "FenestrationSurface:Detailed" || cls == "Window" || cls == "Door" || cls == "GlazedDoor") {
      const std::size_t base = base_surface(o, "building_surface_name");
      const Surface& b = surfaces_[base];
      if (b.kind == "Shading") fail(field(o, "building_surface_name").place, "the base surface is a shading surface");
      s.zone = b.zone;
      s.group = b.group;
      s.opening = true;
      if (cls == "FenestrationSurface:Detailed") {
        const Value& type = field(o, "surface_type");
        for (const char* t : {"Window", "Door", "GlassDoor", "TubularDaylightDome", "TubularDaylightDiffuser"})
          if (same_text(type.text, t)) s.kind = t;
        if (s.kind.empty())
          fail(type.place, "expected Window, Door, GlassDoor, TubularDaylightDome or TubularDaylightDiffuser, not \"" +
                               type.text + "\"");
        s.vertices = raw_vertices(o);
        s.lower_left = lower_left_index(s.vertices.size());
        for (glm::dvec3& p : s.vertices) p = zone_to_model(p, zones_[zone_index_.at(lower(b.zone))]);
      } else {
        s.kind = cls == "GlazedDoor" ? "GlassDoor" : cls;
        s.vertices = rectangle_in_base(o, b);
      }
      const std::size_t index = surfaces_.size();
      add_surface(std::move(s));
      surfaces_[base].openings.push_back(index);
    } else if (cls == "Shading:Zone:Detailed") {
      warn_transmittance(o);
      const std::size_t base = base_surface(o, "base_surface_name");
      const Surface& b = surfaces_[base];
      s.kind = "Shading";
      s.group = Surface::BuildingShading;
      s.vertices = raw_vertices(o);
      s.lower_left = lower_left_index(s.vertices.size());
      if (!b.zone.empty())
        for (glm::dvec3& p : s.vertices) p = zone_to_model(p, zones_[zone_index_.at(lower(b.zone))]);
      add_surface(std::move(s));
    }
  }
}

void Reader::read_window_shades() {
  // Overhangs and fins: drawn from their window or door, which is in model coordinates now.
  for (const Object& o : objects_) {
    const std::string cls = o.spec->name;
    if (cls.rfind("Shading:Overhang", 0) != 0 && cls.rfind("Shading:Fin", 0) != 0) continue;
    const Value& window_name = field(o, "window_or_door_name");
    const auto it = surface_index_.find(lower(window_name.text));
    if (it == surface_index_.end() || !surfaces_[it->second].opening)
      fail(window_name.place, "no window or door named \"" + window_name.text + "\"");
    const std::vector<std::vector<glm::dvec3>> shades = window_shades(o, surfaces_[it->second]);
    for (std::size_t k = 0; k < shades.size(); ++k) {
      Surface s;
      s.object = &o;
      s.kind = "Shading";
      s.group = Surface::BuildingShading;
      s.vertices = shades[k];
      // A fin object gives two shades: "<name> Left" and "<name> Right".
      if (cls.rfind("Shading:Fin", 0) == 0)
        s.name = o.name + (k == 0 && number_or(o, cls == "Shading:Fin" ? "left_depth" : "left_depth_as_fraction_of_window_door_width", 0.0) > 0
                               ? " Left"
                               : " Right");
      add_surface(std::move(s));
    }
  }
}

void Reader::read_surfaces() {
  read_base_surfaces();
  read_openings();
  read_window_shades();
}

}  // namespace shadow::scene_readers::energyplus
