// SPDX-License-Identifier: GPL-3.0-or-later
// EnergyPlus geometry in: IDF and epJSON become one list of objects with positional fields (the
// IDD's order), each field knowing where it was written; the geometry is then built once for
// both syntaxes, so an IDF and its epJSON twin give the same faces bit for bit.
#include "readers/energyplus_reader.hpp"
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

namespace shadow::scene_readers {
namespace {

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out)
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  return out;
}

bool same_text(std::string_view a, std::string_view b) { return lower(a) == lower(b); }

// ---------------------------------------------------------------------------------------------
// Schemas: the fields read, in the IDD's order (IDF position), with the epJSON key of each.

struct FieldSpec {
  const char* idd;  ///< IDD field name, for messages
  const char* key;  ///< epJSON key; nullptr: the object's name (the key of the epJSON object)
};

enum class Vertices { None, List, Four };  // "vertices" array, or vertex_1..4 keys (fenestration)

struct ClassSpec {
  const char* name;
  std::vector<FieldSpec> fields;
  Vertices vertices = Vertices::None;
};

/// `version`: major * 100 + minor (9.6 -> 906); the field lists changed in 9.0 and 9.6.
std::vector<ClassSpec> class_specs(int version) {
  const bool has_space = version >= 906;       // Space Name in surfaces since 9.6
  const bool has_shading_control = version < 900;  // Shading Control Name in windows before 9.0
  auto surface_fields = [&](bool typed) {
    std::vector<FieldSpec> f{{"Name", nullptr}};
    if (typed) f.push_back({"Surface Type", "surface_type"});
    f.push_back({"Construction Name", "construction_name"});
    f.push_back({"Zone Name", "zone_name"});
    if (has_space) f.push_back({"Space Name", "space_name"});
    f.insert(f.end(), {{"Outside Boundary Condition", "outside_boundary_condition"},
                       {"Outside Boundary Condition Object", "outside_boundary_condition_object"},
                       {"Sun Exposure", "sun_exposure"},
                       {"Wind Exposure", "wind_exposure"},
                       {"View Factor to Ground", "view_factor_to_ground"},
                       {"Number of Vertices", "number_of_vertices"}});
    return f;
  };
  std::vector<FieldSpec> fenestration{{"Name", nullptr},
                                      {"Surface Type", "surface_type"},
                                      {"Construction Name", "construction_name"},
                                      {"Building Surface Name", "building_surface_name"},
                                      {"Outside Boundary Condition Object", "outside_boundary_condition_object"},
                                      {"View Factor to Ground", "view_factor_to_ground"}};
  if (has_shading_control) fenestration.push_back({"Shading Control Name", "shading_control_name"});
  fenestration.insert(fenestration.end(), {{"Frame and Divider Name", "frame_and_divider_name"},
                                           {"Multiplier", "multiplier"},
                                           {"Number of Vertices", "number_of_vertices"}});
  auto simple_opening = [&](bool framed) {
    std::vector<FieldSpec> f{{"Name", nullptr}, {"Construction Name", "construction_name"},
                             {"Building Surface Name", "building_surface_name"}};
    if (framed && has_shading_control) f.push_back({"Shading Control Name", "shading_control_name"});
    if (framed) f.push_back({"Frame and Divider Name", "frame_and_divider_name"});
    f.insert(f.end(), {{"Multiplier", "multiplier"},
                       {"Starting X Coordinate", "starting_x_coordinate"},
                       {"Starting Z Coordinate", "starting_z_coordinate"},
                       {"Length", "length"},
                       {"Height", "height"}});
    return f;
  };
  const std::vector<FieldSpec> simple_shading{{"Name", nullptr},
                                              {"Azimuth Angle", "azimuth_angle"},
                                              {"Tilt Angle", "tilt_angle"},
                                              {"Starting X Coordinate", "starting_x_coordinate"},
                                              {"Starting Y Coordinate", "starting_y_coordinate"},
                                              {"Starting Z Coordinate", "starting_z_coordinate"},
                                              {"Length", "length"},
                                              {"Height", "height"}};
  // Wall:Exterior, Roof, Floor:GroundContact, ...: a rectangle from its lower left corner.
  auto simple_surface = [&](bool interzone, const char* size_idd, const char* size_key) {
    std::vector<FieldSpec> f{{"Name", nullptr}, {"Construction Name", "construction_name"}, {"Zone Name", "zone_name"}};
    if (has_space) f.push_back({"Space Name", "space_name"});
    if (interzone) f.push_back({"Outside Boundary Condition Object", "outside_boundary_condition_object"});
    f.insert(f.end(), {{"Azimuth Angle", "azimuth_angle"},
                       {"Tilt Angle", "tilt_angle"},
                       {"Starting X Coordinate", "starting_x_coordinate"},
                       {"Starting Y Coordinate", "starting_y_coordinate"},
                       {"Starting Z Coordinate", "starting_z_coordinate"},
                       {"Length", "length"},
                       {size_idd, size_key}});
    return f;
  };
  const std::vector<FieldSpec> overhang{{"Name", nullptr},
                                        {"Window or Door Name", "window_or_door_name"},
                                        {"Height above Window or Door", "height_above_window_or_door"},
                                        {"Tilt Angle from Window/Door", "tilt_angle_from_window_door"},
                                        {"Left extension from Window/Door Width", "left_extension_from_window_door_width"},
                                        {"Right extension from Window/Door Width", "right_extension_from_window_door_width"},
                                        {"Depth", "depth"}};
  std::vector<FieldSpec> overhang_projection = overhang;
  overhang_projection.back() = {"Depth as Fraction of Window/Door Height", "depth_as_fraction_of_window_door_height"};
  auto fin = [](bool projection) {
    std::vector<FieldSpec> f{{"Name", nullptr}, {"Window or Door Name", "window_or_door_name"}};
    if (projection) {
      f.insert(f.end(), {{"Left Extension from Window/Door", "left_extension_from_window_door"},
                         {"Left Distance Above Top of Window", "left_distance_above_top_of_window"},
                         {"Left Distance Below Bottom of Window", "left_distance_below_bottom_of_window"},
                         {"Left Tilt Angle from Window/Door", "left_tilt_angle_from_window_door"},
                         {"Left Depth as Fraction of Window/Door Width", "left_depth_as_fraction_of_window_door_width"},
                         {"Right Extension from Window/Door", "right_extension_from_window_door"},
                         {"Right Distance Above Top of Window", "right_distance_above_top_of_window"},
                         {"Right Distance Below Bottom of Window", "right_distance_below_bottom_of_window"},
                         {"Right Tilt Angle from Window/Door", "right_tilt_angle_from_window_door"},
                         {"Right Depth as Fraction of Window/Door Width", "right_depth_as_fraction_of_window_door_width"}});
    } else {
      f.insert(f.end(), {{"Left Extension from Window/Door", "left_extension_from_window_door"},
                         {"Left Distance Above Top of Window", "left_distance_above_top_of_window"},
                         {"Left Distance Below Bottom of Window", "left_distance_below_bottom_of_window"},
                         {"Left Tilt Angle from Window/Door", "left_tilt_angle_from_window_door"},
                         {"Left Depth", "left_depth"},
                         {"Right Extension from Window/Door", "right_extension_from_window_door"},
                         {"Right Distance Above Top of Window", "right_distance_above_top_of_window"},
                         {"Right Distance Below Bottom of Window", "right_distance_below_bottom_of_window"},
                         {"Right Tilt Angle from Window/Door", "right_tilt_angle_from_window_door"},
                         {"Right Depth", "right_depth"}});
    }
    return f;
  };
  std::vector<FieldSpec> run_period{{"Name", nullptr}, {"Begin Month", "begin_month"},
                                    {"Begin Day of Month", "begin_day_of_month"}};
  if (version >= 900) run_period.push_back({"Begin Year", "begin_year"});
  run_period.insert(run_period.end(), {{"End Month", "end_month"}, {"End Day of Month", "end_day_of_month"}});
  if (version >= 900) run_period.push_back({"End Year", "end_year"});
  return {
      {"BuildingSurface:Detailed", surface_fields(true), Vertices::List},
      {"Wall:Detailed", surface_fields(false), Vertices::List},
      {"RoofCeiling:Detailed", surface_fields(false), Vertices::List},
      {"Floor:Detailed", surface_fields(false), Vertices::List},
      {"FenestrationSurface:Detailed", fenestration, Vertices::Four},
      {"Window", simple_opening(true)},
      {"Door", simple_opening(false)},
      {"GlazedDoor", simple_opening(true)},
      {"Shading:Site:Detailed",
       {{"Name", nullptr}, {"Transmittance Schedule Name", "transmittance_schedule_name"},
        {"Number of Vertices", "number_of_vertices"}},
       Vertices::List},
      {"Shading:Building:Detailed",
       {{"Name", nullptr}, {"Transmittance Schedule Name", "transmittance_schedule_name"},
        {"Number of Vertices", "number_of_vertices"}},
       Vertices::List},
      {"Shading:Zone:Detailed",
       {{"Name", nullptr}, {"Base Surface Name", "base_surface_name"},
        {"Transmittance Schedule Name", "transmittance_schedule_name"},
        {"Number of Vertices", "number_of_vertices"}},
       Vertices::List},
      {"Wall:Exterior", simple_surface(false, "Height", "height")},
      {"Wall:Adiabatic", simple_surface(false, "Height", "height")},
      {"Wall:Underground", simple_surface(false, "Height", "height")},
      {"Wall:Interzone", simple_surface(true, "Height", "height")},
      {"Roof", simple_surface(false, "Width", "width")},
      {"Ceiling:Adiabatic", simple_surface(false, "Width", "width")},
      {"Ceiling:Interzone", simple_surface(true, "Width", "width")},
      {"Floor:GroundContact", simple_surface(false, "Width", "width")},
      {"Floor:Adiabatic", simple_surface(false, "Width", "width")},
      {"Floor:Interzone", simple_surface(true, "Width", "width")},
      {"Shading:Overhang", overhang},
      {"Shading:Overhang:Projection", overhang_projection},
      {"Shading:Fin", fin(false)},
      {"Shading:Fin:Projection", fin(true)},
      {"Shading:Site", simple_shading},
      {"Shading:Building", simple_shading},
      {"Zone",
       {{"Name", nullptr}, {"Direction of Relative North", "direction_of_relative_north"},
        {"X Origin", "x_origin"}, {"Y Origin", "y_origin"}, {"Z Origin", "z_origin"}}},
      {"Building", {{"Name", nullptr}, {"North Axis", "north_axis"}}},
      {"GlobalGeometryRules",
       {{"Starting Vertex Position", "starting_vertex_position"},
        {"Vertex Entry Direction", "vertex_entry_direction"},
        {"Coordinate System", "coordinate_system"},
        {"Daylighting Reference Point Coordinate System", "daylighting_reference_point_coordinate_system"},
        {"Rectangular Surface Coordinate System", "rectangular_surface_coordinate_system"}}},
      {"Site:Location",
       {{"Name", nullptr}, {"Latitude", "latitude"}, {"Longitude", "longitude"},
        {"Time Zone", "time_zone"}, {"Elevation", "elevation"}}},
      {"RunPeriod", run_period},
      {"Timestep", {{"Number of Timesteps per Hour", "number_of_timesteps_per_hour"}}},
  };
}

/// Geometry classes this reader does not build: their objects are reported, never silently lost.
/// (Window:Interzone and Door:Interzone are skipped without a word: they sit in interzone
/// surfaces, which are left out anyway.)
const std::vector<std::string>& unsupported_geometry_classes() {
  static const std::vector<std::string> classes{
      "InternalMass", "GeometryTransform"};
  return classes;
}

// ---------------------------------------------------------------------------------------------
// Objects with positional fields, from either syntax.

struct Value {
  bool present = false;
  std::string text;  ///< IDF text or JSON string (empty for a JSON number)
  std::optional<double> json_number;
  std::string place;  ///< where the field is, for messages
};

struct Object {
  const ClassSpec* spec = nullptr;
  std::string name;
  std::string place;  ///< the object's place (Face::source)
  std::vector<Value> fields;                   ///< spec->fields.size() entries
  std::vector<std::array<Value, 3>> vertices;  ///< Vertices::List / Four
  std::string vertex_problem;                  ///< IDF: a vertex left with fewer than 3 coordinates
  std::string vertex_problem_place;
};

class Reader {
 public:
  Reader(std::string display_name, const LoadOptions& options) : file_(std::move(display_name)), options_(options) {}

  Model read(const std::string& text, bool epjson);

 private:
  // --- fields ---
  [[noreturn]] void fail(const std::string& place, const std::string& problem) const {
    throw InputError({file_, place}, problem);
  }
  const Value& field(const Object& o, std::string_view key) const;
  std::string text(const Object& o, std::string_view key) const { return field(o, key).text; }
  std::optional<double> number(const Value& v) const;
  double number_or(const Object& o, std::string_view key, double fallback) const {
    return number(field(o, key)).value_or(fallback);
  }
  double required_number(const Value& v, const char* what) const {
    const std::optional<double> x = number(v);
    if (!x) fail(v.place, std::string("missing ") + what);
    return *x;
  }

  // --- the two syntaxes ---
  void load_idf(const std::string& text);
  void load_epjson(const std::string& text);
  const ClassSpec* find_spec(std::string_view class_name) const;

  // --- geometry ---
  struct Surface {
    const Object* object = nullptr;
    std::string kind;
    std::string zone;                 ///< zone name as written by the Zone object ("" for shading)
    enum Group { ZoneGroup, BuildingShading, SiteShading, NotExposed, Dropped } group = ZoneGroup;
    std::vector<glm::dvec3> vertices;  ///< model coordinates, counter-clockwise seen from outside
    std::vector<std::size_t> openings;
    bool opening = false;
    std::string name;  ///< the object's name, or "<fin> Left"/"<fin> Right" for a fin's two shades
  };
  struct ZoneFrame {
    std::string name;
    double north = 0.0;
    glm::dvec3 origin{0.0};
    std::string place;
  };
  std::vector<glm::dvec3> raw_vertices(const Object& o) const;
  glm::dvec3 zone_to_model(const glm::dvec3& p, const ZoneFrame& zone) const;
  glm::dvec3 world_to_model(const glm::dvec3& p) const;
  const ZoneFrame& zone_of(const Object& o, std::string_view key) const;
  std::size_t base_surface(const Object& o, std::string_view key) const;
  std::vector<glm::dvec3> rectangle_in_base(const Object& o, const Surface& base) const;
  std::vector<std::vector<glm::dvec3>> window_shades(const Object& o, const Surface& window) const;
  std::vector<glm::dvec3> rectangle(const Object& o, double default_tilt, const char* size_key,
                                    double extra_azimuth = 0.0) const;
  void read_globals();
  void read_surfaces();
  void warn_transmittance(const Object& o);
  void check_names();
  void cut_and_emit(Model& model);
  // Openings off their wall's plane (energyplus_reveals.hpp): checked, reveals added, reported.
  void check_placement(const Surface& opening, const Surface& base, const OpeningPlacement& placement,
                       double allowed);
  void add_reveal(const Surface& opening, const OpeningPlacement& placement, std::vector<Face>& out);
  void report_reveals();
  struct RevealCount {
    std::size_t openings = 0;
    double shallowest = 0.0, deepest = 0.0;
    const Surface* first = nullptr;
  } set_back_, proud_;
  std::optional<SunPeriod> read_sun();

  std::string file_;
  LoadOptions options_;
  int version_ = 2420;
  std::vector<ClassSpec> specs_;
  std::vector<Object> objects_;
  std::map<std::string, std::pair<std::size_t, std::string>> ignored_;  // lower class -> count, spelling
  std::vector<Warning> warnings_;

  bool clockwise_ = false;
  bool world_ = false;  // GlobalGeometryRules Coordinate System World/Absolute
  bool rectangular_world_ = false;
  double north_axis_ = 0.0;
  std::vector<ZoneFrame> zones_;
  std::map<std::string, std::size_t> zone_index_;  // lower name -> zones_
  std::vector<Surface> surfaces_;
  std::map<std::string, std::size_t> surface_index_;  // lower name -> surfaces_
};

const ClassSpec* Reader::find_spec(std::string_view class_name) const {
  for (const ClassSpec& spec : specs_)
    if (same_text(spec.name, class_name)) return &spec;
  return nullptr;
}

const Value& Reader::field(const Object& o, std::string_view key) const {
  for (std::size_t i = 0; i < o.spec->fields.size(); ++i) {
    const char* k = o.spec->fields[i].key;
    if (k != nullptr && key == k) return o.fields[i];
  }
  static const Value none;
  return none;  // a field of another EnergyPlus version: absent
}

std::optional<double> Reader::number(const Value& v) const {
  if (!v.present) return std::nullopt;
  if (v.json_number) return *v.json_number;
  std::string_view t = v.text;
  if (t.empty() || same_text(t, "autocalculate")) return std::nullopt;
  if (t.front() == '+') t.remove_prefix(1);
  double x = 0.0;
  const auto [end, error] = std::from_chars(t.data(), t.data() + t.size(), x);
  if (error != std::errc() || end != t.data() + t.size() || !std::isfinite(x))
    fail(v.place, "not a number: \"" + v.text + "\"");
  return x;
}

/// True for a version identifier as EnergyPlus writes one: "9.6", "24.1.0" (one to three
/// whole numbers separated by dots).
bool is_version_text(std::string_view text) {
  int parts = 0;
  for (std::size_t at = 0;;) {
    const std::size_t start = at;
    while (at < text.size() && text[at] >= '0' && text[at] <= '9') ++at;
    if (at == start) return false;
    ++parts;
    if (at == text.size()) return parts <= 3;
    if (text[at] != '.') return false;
    ++at;
  }
}

/// "9.6", "24.1.0" -> major * 100 + minor; a blank field or a major beyond 999 (no EnergyPlus
/// version) leaves `fallback`, the current field lists. Text that is no version is an error at
/// `place`: read with the wrong field lists, every surface would be misread.
int parse_version(const std::string& text, int fallback, const std::string& file, const std::string& place) {
  if (text.empty()) return fallback;  // left blank: the current field lists
  if (!is_version_text(text))
    throw InputError({file, place}, "expected an EnergyPlus version like 24.1 or 9.6, not " +
                                        json_string(text));
  int major = 0, minor = 0;
  const char* end = text.data() + text.size();
  const auto [after_major, e1] = std::from_chars(text.data(), end, major);
  if (e1 != std::errc() || major < 1 || major > 999) return fallback;
  if (after_major < end && *after_major == '.') {
    const auto [after_minor, e2] = std::from_chars(after_major + 1, end, minor);
    if (e2 != std::errc() || minor < 0 || minor > 99) minor = 0;
  }
  return major * 100 + minor;
}

/// epJSON keys whose values are names or choices (strings), not numbers: `17` there is a
/// mistake, not a zone called "17" (an IDF has no types, and a name may be any text there).
bool is_text_key(std::string_view key) {
  static constexpr std::string_view choices[] = {
      "surface_type", "outside_boundary_condition", "outside_boundary_condition_object", "sun_exposure",
      "wind_exposure", "starting_vertex_position", "vertex_entry_direction", "coordinate_system",
      "daylighting_reference_point_coordinate_system", "rectangular_surface_coordinate_system"};
  const std::string_view suffix = "_name";
  if (key.size() > suffix.size() && key.substr(key.size() - suffix.size()) == suffix) return true;
  return std::find(std::begin(choices), std::end(choices), key) != std::end(choices);
}

/// How epJSON paths spell members: the class and the object name always in brackets
/// (`["Zone"]["Z1"]`), fields as members (`.x_origin`).
std::string epjson_member(const std::string& path, std::size_t depth, const std::string& key) {
  return depth < 2 ? path + "[" + json_string(key) + "]" : member(path, key);
}

// IDF: objects come out of the tokenizer; the Version object picks the field lists first.
void Reader::load_idf(const std::string& text) {
  const std::vector<IdfObject> idf = tokenize_idf(text, file_);
  for (const IdfObject& o : idf)
    if (same_text(o.fields[0].text, "Version") && o.fields.size() > 1) {
      version_ = parse_version(o.fields[1].text, version_, file_,
                               "line " + std::to_string(o.fields[1].line) + ", Version field \"Version Identifier\"");
    }
  specs_ = class_specs(version_);
  for (const IdfObject& o : idf) {
    const ClassSpec* spec = find_spec(o.fields[0].text);
    if (spec == nullptr) {
      auto& entry = ignored_[lower(o.fields[0].text)];
      if (entry.first++ == 0) entry.second = o.fields[0].text;
      continue;
    }
    Object obj;
    obj.spec = spec;
    const bool named = spec->fields.front().key == nullptr;
    obj.name = named && o.fields.size() > 1 ? o.fields[1].text : "";
    const std::string head = std::string(spec->name) + (named ? " \"" + obj.name + "\"" : "");
    obj.place = "line " + std::to_string(o.line) + ", " + head;
    for (std::size_t i = 0; i < spec->fields.size(); ++i) {
      Value v;
      const std::size_t at = i + 1;
      v.present = at < o.fields.size() && !o.fields[at].text.empty();
      if (at < o.fields.size()) v.text = o.fields[at].text;
      const std::size_t line = at < o.fields.size() ? o.fields[at].line : o.line;
      v.place = "line " + std::to_string(line) + ", " + head + " field \"" + spec->fields[i].idd + "\"";
      obj.fields.push_back(std::move(v));
    }
    if (spec->vertices != Vertices::None) {
      // Trailing blank fields are no vertices (IDF editors leave them).
      std::size_t end = o.fields.size();
      while (end > spec->fields.size() + 1 && o.fields[end - 1].text.empty()) --end;
      const char axes[3] = {'X', 'Y', 'Z'};
      for (std::size_t at = spec->fields.size() + 1, n = 1; at < end; at += 3, ++n) {
        std::array<Value, 3> vertex;
        for (int c = 0; c < 3; ++c) {
          Value& v = vertex[c];
          const std::size_t here = at + c;
          v.present = here < end && !o.fields[here].text.empty();
          if (here < end) v.text = o.fields[here].text;
          const std::size_t line = here < end ? o.fields[here].line : o.fields[end - 1].line;
          v.place = "line " + std::to_string(line) + ", " + head + " field \"Vertex " + std::to_string(n) + " " +
                    axes[c] + "-coordinate\"";
          if (here >= end && obj.vertex_problem.empty()) {
            obj.vertex_problem = "vertex " + std::to_string(n) + " has only " + std::to_string(c) +
                                 " of its 3 coordinates";
            obj.vertex_problem_place = v.place;
          }
        }
        obj.vertices.push_back(std::move(vertex));
      }
    }
    objects_.push_back(std::move(obj));
  }
}

// epJSON: {"Class": {"object name": {"key": value, ...}}}.
void Reader::load_epjson(const std::string& text) {
  // ordered_json: objects keep the file's order, as IDF objects do (face order follows it).
  // Syntax errors at their line and column, a number beyond a double at its path, and an object
  // name written twice in one class (JSON would keep only one of the two objects) refused.
  const nlohmann::ordered_json root = parse_json_document<nlohmann::ordered_json>(text, file_, epjson_member);
  if (!root.is_object()) fail("", "an epJSON file must hold a JSON object (class -> objects), got " + describe(root));
  for (auto c = root.begin(); c != root.end(); ++c)
    if (same_text(c.key(), "Version") && c.value().is_object())
      for (auto& [name, fields] : c.value().items()) {
        if (!fields.is_object()) continue;
        const auto identifier = fields.find("version_identifier");
        if (identifier == fields.end()) continue;
        const std::string place = "[" + json_string(c.key()) + "][" + json_string(name) + "].version_identifier";
        if (!identifier->is_string())
          fail(place, "expected an EnergyPlus version like \"24.1\" (a string), got " + describe(*identifier));
        version_ = parse_version(identifier->get<std::string>(), version_, file_, place);
      }
  specs_ = class_specs(version_);
  auto to_value = [&](const nlohmann::ordered_json* j, const std::string& place, std::string_view key) {
    Value v;
    v.place = place;
    if (j == nullptr || j->is_null()) return v;
    if (j->is_number()) {
      if (is_text_key(key)) fail(place, "expected a name (a JSON string), got " + describe(*j));
      v.present = true;
      v.json_number = j->get<double>();
    } else if (j->is_string()) {
      v.text = j->get<std::string>();
      v.present = !v.text.empty();
    } else {
      fail(place, "expected a number or a string, got " + describe(*j));
    }
    return v;
  };
  for (auto c = root.begin(); c != root.end(); ++c) {
    const ClassSpec* spec = find_spec(c.key());
    if (spec == nullptr) {
      auto& entry = ignored_[lower(c.key())];
      entry.second = c.key();
      entry.first += c.value().is_object() ? c.value().size() : 1;
      continue;
    }
    const std::string class_path = "[" + json_string(c.key()) + "]";
    if (!c.value().is_object()) fail(class_path, "expected an object of named " + std::string(spec->name) + " objects");
    for (auto o = c.value().begin(); o != c.value().end(); ++o) {
      const std::string path = class_path + "[" + json_string(o.key()) + "]";
      if (!o.value().is_object()) fail(path, "expected an object of fields");
      const nlohmann::ordered_json& fields = o.value();
      Object obj;
      obj.spec = spec;
      const bool named = spec->fields.front().key == nullptr;
      obj.name = named ? o.key() : "";
      obj.place = path;
      for (const FieldSpec& f : spec->fields) {
        if (f.key == nullptr) {
          Value v;
          v.present = !o.key().empty();
          v.text = o.key();
          v.place = path;
          obj.fields.push_back(std::move(v));
          continue;
        }
        const auto it = fields.find(f.key);
        obj.fields.push_back(to_value(it == fields.end() ? nullptr : &*it, path + "." + f.key, f.key));
      }
      const char* axes[3] = {"x", "y", "z"};
      if (spec->vertices == Vertices::List) {
        const auto it = fields.find("vertices");
        if (it != fields.end()) {
          if (!it->is_array()) fail(path + ".vertices", "expected an array of vertices");
          for (std::size_t n = 0; n < it->size(); ++n) {
            const nlohmann::ordered_json& vertex = (*it)[n];
            const std::string vpath = path + ".vertices[" + std::to_string(n) + "]";
            if (!vertex.is_object()) fail(vpath, "expected an object with vertex_x_coordinate, ...");
            std::array<Value, 3> out;
            for (int a = 0; a < 3; ++a) {
              const std::string key = std::string("vertex_") + axes[a] + "_coordinate";
              const auto f = vertex.find(key);
              out[a] = to_value(f == vertex.end() ? nullptr : &*f, vpath + "." + key, key);
            }
            obj.vertices.push_back(std::move(out));
          }
        }
      } else if (spec->vertices == Vertices::Four) {
        for (int n = 1; n <= 4; ++n) {
          std::array<Value, 3> out;
          bool any = false;
          for (int a = 0; a < 3; ++a) {
            const std::string key = "vertex_" + std::to_string(n) + "_" + axes[a] + "_coordinate";
            const auto f = fields.find(key);
            out[a] = to_value(f == fields.end() ? nullptr : &*f, path + "." + key, key);
            any = any || out[a].present;
          }
          if (any) obj.vertices.push_back(std::move(out));
        }
      }
      objects_.push_back(std::move(obj));
    }
  }
}

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

glm::dvec3 Reader::zone_to_model(const glm::dvec3& p, const ZoneFrame& zone) const {
  if (world_) return p;
  const glm::dvec3 r = rotate_clockwise_frame(p, zone.north);
  return {r.x + zone.origin.x, r.y + zone.origin.y, r.z + zone.origin.z};
}

// World (true north) to building coordinates: the building's +y is north_axis_ clockwise from
// true north, so a world point's building coordinates turn the other way.
glm::dvec3 Reader::world_to_model(const glm::dvec3& p) const {
  if (world_) return p;
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

// Window, Door, GlazedDoor: a rectangle given in its base surface's own coordinates (x along
// the surface to the right seen from outside, z up the surface; origin at its lower left).
/// A planar surface's own coordinates, as EnergyPlus's simple windows and shades use them: x to
/// the right seen from outside (horizontal), y up the surface, n out; origin at the lower left
/// of the surface's bounding rectangle in x and y, which spans [0, width] x [0, height].
struct SurfaceFrame {
  glm::dvec3 corner, right, up, n;
  double width = 0.0, height = 0.0;
  [[nodiscard]] glm::dvec3 at(double u, double v) const { return corner + u * right + v * up; }
};

std::optional<SurfaceFrame> surface_frame(const std::vector<glm::dvec3>& b) {
  SurfaceFrame f;
  f.n = geometry::newell_normal(b, b.front());
  const double n_length = std::sqrt(f.n.x * f.n.x + f.n.y * f.n.y + f.n.z * f.n.z);
  if (!(n_length > 0)) return std::nullopt;
  f.n /= n_length;
  // Right seen from outside: up x n; for a horizontal surface, the model's +x (roof) or -x (floor).
  f.right = glm::dvec3(-f.n.y, f.n.x, 0.0);
  const double r = std::sqrt(f.right.x * f.right.x + f.right.y * f.right.y);
  if (r < 1e-9)
    f.right = glm::dvec3(f.n.z > 0 ? 1.0 : -1.0, 0.0, 0.0);
  else
    f.right /= r;
  const glm::dvec3& n = f.n;
  const glm::dvec3& x = f.right;
  f.up = glm::dvec3(n.y * x.z - n.z * x.y, n.z * x.x - n.x * x.z, n.x * x.y - n.y * x.x);
  double min_x = 0, min_y = 0, max_x = 0, max_y = 0;
  for (std::size_t i = 0; i < b.size(); ++i) {
    const glm::dvec3 d = b[i] - b.front();
    const double px = d.x * f.right.x + d.y * f.right.y + d.z * f.right.z;
    const double py = d.x * f.up.x + d.y * f.up.y + d.z * f.up.z;
    if (i == 0 || px < min_x) min_x = px;
    if (i == 0 || py < min_y) min_y = py;
    if (i == 0 || px > max_x) max_x = px;
    if (i == 0 || py > max_y) max_y = py;
  }
  f.corner = b.front() + min_x * f.right + min_y * f.up;
  f.width = max_x - min_x;
  f.height = max_y - min_y;
  return f;
}

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
  const std::optional<SurfaceFrame> f = surface_frame(base.vertices);
  if (!f) fail(o.place, "its base surface has zero area");
  return {f->at(x, z), f->at(x + length, z), f->at(x + length, z + height), f->at(x, z + height)};
}

// Shading:Overhang(:Projection) and Shading:Fin(:Projection): shades drawn from their window or
// door. The angle from the window is 90 for a shade square to it; below 90 it turns toward the
// wall beyond the window's edge (up for an overhang, outward sideways for a fin).
std::vector<std::vector<glm::dvec3>> Reader::window_shades(const Object& o, const Surface& window) const {
  const std::optional<SurfaceFrame> f = surface_frame(window.vertices);
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
    const glm::dvec3 away = left_side ? -f->right : f->right;
    const glm::dvec3 out = depth * (s * f->n + c * away);
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
                                          double extra_azimuth) const {
  const double azimuth = required_number(field(o, "azimuth_angle"), "azimuth angle") + extra_azimuth;
  const double tilt = number_or(o, "tilt_angle", default_tilt);
  const glm::dvec3 start(number_or(o, "starting_x_coordinate", 0.0), number_or(o, "starting_y_coordinate", 0.0),
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

void Reader::read_globals() {
  for (const Object& o : objects_) {
    const std::string cls = o.spec->name;
    if (cls == "GlobalGeometryRules") {
      const Value& direction = field(o, "vertex_entry_direction");
      if (same_text(direction.text, "Clockwise"))
        clockwise_ = true;
      else if (direction.present && !same_text(direction.text, "Counterclockwise"))
        fail(direction.place, "expected Counterclockwise or Clockwise, not \"" + direction.text + "\"");
      for (const char* key : {"coordinate_system", "rectangular_surface_coordinate_system"}) {
        const Value& system = field(o, key);
        const bool world = same_text(system.text, "World") || same_text(system.text, "Absolute");
        if (system.present && !world && !same_text(system.text, "Relative"))
          fail(system.place, "expected Relative, World or Absolute, not \"" + system.text + "\"");
        (std::string_view(key) == "coordinate_system" ? world_ : rectangular_world_) = world;
      }
    } else if (cls == "Building") {
      north_axis_ = number_or(o, "north_axis", 0.0);
    } else if (cls == "Zone") {
      ZoneFrame zone{o.name, number_or(o, "direction_of_relative_north", 0.0),
                     {number_or(o, "x_origin", 0.0), number_or(o, "y_origin", 0.0), number_or(o, "z_origin", 0.0)},
                     o.place};
      if (!zone_index_.emplace(lower(o.name), zones_.size()).second)
        fail(o.place, "a second Zone named \"" + o.name + "\"");
      zones_.push_back(std::move(zone));
    }
  }
  if (world_) {
    // EnergyPlus ignores these with world coordinates; say so rather than drop them silently.
    bool moved = north_axis_ != 0.0;
    for (const ZoneFrame& z : zones_) moved = moved || z.north != 0.0 || z.origin != glm::dvec3(0.0);
    if (moved)
      warnings_.push_back({{file_, "GlobalGeometryRules"},
                           "world coordinates: Building North Axis, zone origins and zone directions of "
                           "relative north are ignored, as EnergyPlus does"});
    north_axis_ = 0.0;
  }
}

// Shading is opaque here: a transmittance schedule (a tree in leaf) is not applied, and said so.
void Reader::warn_transmittance(const Object& o) {
  const Value& schedule = field(o, "transmittance_schedule_name");
  if (schedule.present)
    warnings_.push_back({{file_, schedule.place}, "transmittance schedule \"" + schedule.text +
                                                      "\" not applied: libshadow's shading surfaces are opaque"});
}

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

void Reader::read_surfaces() {
  auto add = [&](Surface s) {
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
  };
  auto boundary_group = [&](const Object& o) {
    const Value& boundary = field(o, "outside_boundary_condition");
    const Value& sun = field(o, "sun_exposure");
    if (same_text(boundary.text, "Surface") || same_text(boundary.text, "Zone")) return Surface::Dropped;
    if (same_text(boundary.text, "Outdoors") && !same_text(sun.text, "NoSun")) return Surface::ZoneGroup;
    if (!boundary.present) fail(boundary.place, "missing outside boundary condition");
    return Surface::NotExposed;
  };
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
      for (glm::dvec3& p : s.vertices) p = zone_to_model(p, zone);
      add(std::move(s));
    } else if (const SimpleSurface* simple = simple_surface(cls)) {
      const ZoneFrame& zone = zone_of(o, "zone_name");
      s.zone = zone.name;
      s.kind = simple->kind;
      s.group = static_cast<Surface::Group>(simple->group);
      if (rectangular_world_ && !world_) {
        // Corner in world coordinates; the azimuth is still taken relative to the building and
        // turned with the zone (EnergyPlus), so the building-frame shape is drawn at the corner.
        s.vertices = rectangle(o, simple->tilt, simple->size_key, zone.north);
        const glm::dvec3 corner = s.vertices.front();
        const glm::dvec3 moved = world_to_model(corner);
        for (glm::dvec3& p : s.vertices) p = moved + (p - corner);
      } else {
        s.vertices = rectangle(o, simple->tilt, simple->size_key);
        for (glm::dvec3& p : s.vertices) p = zone_to_model(p, zone);
      }
      add(std::move(s));
    } else if (cls == "Shading:Site:Detailed" || cls == "Shading:Building:Detailed") {
      warn_transmittance(o);
      s.kind = "Shading";
      s.group = cls == "Shading:Site:Detailed" ? Surface::SiteShading : Surface::BuildingShading;
      s.vertices = raw_vertices(o);
      if (s.group == Surface::SiteShading)
        for (glm::dvec3& p : s.vertices) p = world_to_model(p);
      add(std::move(s));
    } else if (cls == "Shading:Site" || cls == "Shading:Building") {
      s.kind = "Shading";
      s.group = cls == "Shading:Site" ? Surface::SiteShading : Surface::BuildingShading;
      s.vertices = rectangle(o, 90.0, "height");
      if (s.group == Surface::SiteShading)
        for (glm::dvec3& p : s.vertices) p = world_to_model(p);
      add(std::move(s));
    }
  }
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
        for (glm::dvec3& p : s.vertices) p = zone_to_model(p, zones_[zone_index_.at(lower(b.zone))]);
      } else {
        s.kind = cls == "GlazedDoor" ? "GlassDoor" : cls;
        s.vertices = rectangle_in_base(o, b);
      }
      const std::size_t index = surfaces_.size();
      add(std::move(s));
      surfaces_[base].openings.push_back(index);
    } else if (cls == "Shading:Zone:Detailed") {
      warn_transmittance(o);
      const std::size_t base = base_surface(o, "base_surface_name");
      const Surface& b = surfaces_[base];
      s.kind = "Shading";
      s.group = Surface::BuildingShading;
      s.vertices = raw_vertices(o);
      if (!b.zone.empty())
        for (glm::dvec3& p : s.vertices) p = zone_to_model(p, zones_[zone_index_.at(lower(b.zone))]);
      add(std::move(s));
    }
  }
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
      add(std::move(s));
    }
  }
}

// Each base surface loses its openings (exactly), and is split into hole-free pieces that share
// its name; meshes: the zones in Zone order, then building shading, site shading, not exposed.
void Reader::cut_and_emit(Model& model) {
  const int groups = 4;
  std::vector<std::vector<Face>> per_zone(zones_.size());
  std::vector<std::vector<Face>> per_group(groups);
  for (std::size_t i = 0; i < surfaces_.size(); ++i) {
    const Surface& s = surfaces_[i];
    if (s.opening || s.group == Surface::Dropped) continue;
    std::vector<Face>& out = s.group == Surface::ZoneGroup ? per_zone[zone_index_.at(lower(s.zone))] : per_group[s.group];
    auto face = [&](const Surface& surface, std::vector<glm::dvec3> vertices) {
      Face f;
      f.vertices = std::move(vertices);
      f.source = {file_, surface.object->place};
      f.name = surface.name;
      f.kind = surface.kind;
      out.push_back(std::move(f));
    };
    if (s.openings.empty()) {
      face(s, s.vertices);
      continue;
    }
    // Openings must lie in the base surface's plane (within the planarity tolerance) ...
    const glm::dvec3 origin = s.vertices.front();
    glm::dvec3 n = geometry::newell_normal(s.vertices, origin);
    const double n_length = std::sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
    if (!(n_length > 0)) fail(s.object->place, "a surface with openings has zero area");
    n /= n_length;
    glm::dvec3 lo = s.vertices.front(), hi = lo;
    for (const glm::dvec3& p : s.vertices) {
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
    }
    const double diameter = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
    const double allowed = options_.planarity_tolerance * diameter;
    std::vector<std::vector<glm::dvec3>> openings;
    std::vector<OpeningPlacement> placements;
    for (const std::size_t o : s.openings) {
      const Surface& opening = surfaces_[o];
      // In the plane, or parallel to it and set back (a reveal) or proud: energyplus_reveals.
      OpeningPlacement placement = place_opening(opening.vertices, origin, n, allowed);
      check_placement(opening, s, placement, allowed);
      const glm::dvec3 on = geometry::newell_normal(opening.vertices, opening.vertices.front());
      if (on.x * n.x + on.y * n.y + on.z * n.z < 0)
        fail(opening.object->place, "faces the other way from its base surface \"" + s.object->name +
                                        "\" (its vertices run the other way round)");
      openings.push_back(placement.outline);
      placements.push_back(std::move(placement));
    }
    // ... and inside it, without overlapping each other: exact predicates on the input doubles.
    const detail::OpeningsCut cut = detail::cut_openings(s.vertices, openings, allowed);
    if (cut.surface_not_simple) fail(s.object->place, "the surface has zero area or crosses itself");
    if (cut.not_simple >= 0)
      fail(surfaces_[s.openings[cut.not_simple]].object->place, "the opening has zero area or crosses itself");
    if (cut.outside >= 0)
      fail(surfaces_[s.openings[cut.outside]].object->place,
           "not inside its base surface \"" + s.name + "\"");
    if (cut.overlap_first >= 0)
      fail(surfaces_[s.openings[cut.overlap_second]].object->place,
           "overlaps \"" + surfaces_[s.openings[cut.overlap_first]].name + "\" in the same base surface");
    if (cut.within_tolerance)
      warnings_.push_back({{file_, s.object->place},
                           "an opening sticks out of the surface, or two openings overlap, by no more than the "
                           "planarity tolerance (" + detail::format_number(allowed) +
                               "): taken as rounding, the cut is exact up to those slivers"});
    for (const auto& region : cut.regions) {
      if (region.size() == 1) {
        face(s, region.front());
        continue;
      }
      const std::vector<std::vector<glm::dvec3>> holes(region.begin() + 1, region.end());
      const core::PolygonHolesSplit split =
          core::split_polygon_with_holes_checked(region.front(), holes, options_.planarity_tolerance);
      if (!split.error.empty()) fail(s.object->place, "cutting its openings out: " + split.error);
      for (const auto& piece : split.pieces) face(s, piece);
    }
    for (std::size_t k = 0; k < s.openings.size(); ++k) {
      const Surface& opening = surfaces_[s.openings[k]];
      const OpeningPlacement& placement = placements[k];
      // A window in a reveal stays at its depth, and the reveal's sides shade it; one proud of
      // its wall is put into the wall's plane (EnergyPlus gives it no projection either).
      face(opening, placement.kind == OpeningPlacement::Proud ? placement.outline : opening.vertices);
      if (placement.kind == OpeningPlacement::SetBack)
        add_reveal(opening, placement, per_group[Surface::BuildingShading]);
    }
  }
  report_reveals();
  auto emit = [&](const std::string& name, std::vector<Face>& faces, bool receiver, const char* type) {
    if (faces.empty()) return;
    Mesh mesh;
    mesh.name = name;
    mesh.object_type = type;  // a zone's results add up per zone (sun_hours_by_object.csv)
    mesh.first_face = model.faces.size();
    mesh.face_count = faces.size();
    mesh.receiver = receiver;
    const std::size_t index = model.meshes.size();
    for (Face& f : faces) {
      f.mesh = index;
      model.faces.push_back(std::move(f));
    }
    model.meshes.push_back(std::move(mesh));
  };
  for (std::size_t z = 0; z < zones_.size(); ++z) emit(zones_[z].name, per_zone[z], true, "zone");
  emit("Shading:Building", per_group[Surface::BuildingShading], false, "");
  emit("Shading:Site", per_group[Surface::SiteShading], false, "");
  emit("Not exposed", per_group[Surface::NotExposed], false, "");
}

// An opening off its wall's plane: in a reveal (set back) or proud of the wall, both parallel to
// it and at most kMaxRevealDepth away, is read (docs/energyplus.md); anything else is an error.
void Reader::check_placement(const Surface& opening, const Surface& base, const OpeningPlacement& placement,
                             double allowed) {
  const std::string plane = "not in the plane of its base surface \"" + base.object->name + "\": ";
  if (placement.kind == OpeningPlacement::Skew)
    fail(opening.object->place, plane + "vertex " + detail::format_vec(placement.vertex) + " is " +
                                    detail::format_number(placement.distance) +
                                    " off it, and the opening is not parallel to it (its vertices' distances "
                                    "differ by more than " + detail::format_number(allowed) +
                                    "), so it is no window in a reveal either");
  if (placement.kind == OpeningPlacement::TooDeep)
    fail(opening.object->place, plane + "it lies " + detail::format_number(std::abs(placement.offset)) +
                                    (placement.offset < 0 ? " behind" : " in front of") +
                                    " it, more than the deepest reveal read (" +
                                    detail::format_number(kMaxRevealDepth) + " m; docs/energyplus.md)");
  if (placement.kind != OpeningPlacement::SetBack && placement.kind != OpeningPlacement::Proud) return;
  RevealCount& count = placement.kind == OpeningPlacement::SetBack ? set_back_ : proud_;
  const double depth = std::abs(placement.offset);
  count.shallowest = count.openings == 0 ? depth : std::min(count.shallowest, depth);
  count.deepest = count.openings == 0 ? depth : std::max(count.deepest, depth);
  if (count.openings++ == 0) count.first = &opening;
}

// The reveal's sides of a set-back opening: building shading named after it, and counted.
void Reader::add_reveal(const Surface& opening, const OpeningPlacement& placement, std::vector<Face>& out) {
  const std::vector<std::vector<glm::dvec3>> sides = reveal_sides(opening.vertices, placement.outline);
  for (std::size_t k = 0; k < sides.size(); ++k) {
    Face f;
    f.vertices = sides[k];
    f.source = {file_, opening.object->place};
    f.name = opening.name + ":Reveal:" + std::to_string(k + 1);
    f.kind = "Shading";
    if (surface_index_.count(lower(f.name)) != 0)
      fail(opening.object->place, "its reveal's side would be named \"" + f.name +
                                      "\", which another surface already is (" +
                                      surfaces_[surface_index_.at(lower(f.name))].object->place + ")");
    out.push_back(std::move(f));
  }
}

// One warning for all set-back openings, one for all proud ones: a model has dozens of windows.
void Reader::report_reveals() {
  auto depths = [](const RevealCount& c) {
    return c.shallowest == c.deepest ? detail::format_number(c.deepest) + " m"
                                     : detail::format_number(c.shallowest) + " to " + detail::format_number(c.deepest) + " m";
  };
  auto openings = [](const RevealCount& c) {
    return std::to_string(c.openings) + (c.openings == 1 ? " window or door" : " windows and doors") + " (first \"" +
           c.first->name + "\")";
  };
  if (set_back_.openings > 0)
    warnings_.push_back({{file_, set_back_.first->object->place},
                         openings(set_back_) + " set back from the plane of their base surface by " + depths(set_back_) +
                             ": read as openings in reveals of that depth; each reveal's sides (jambs, head, sill) "
                             "are building shading named \"<opening>:Reveal:1\", \"<opening>:Reveal:2\", ... "
                             "(docs/energyplus.md)"});
  if (proud_.openings > 0)
    warnings_.push_back({{file_, proud_.first->object->place},
                         openings(proud_) + " in front of the plane of their base surface by " + depths(proud_) +
                             ": put into that plane, as EnergyPlus gives an opening proud of its wall no reveal "
                             "(docs/energyplus.md)"});
}

bool is_leap(int y) { return is_valid_date(y, 2, 29); }  // shadow/sun.hpp's calendar

std::optional<SunPeriod> Reader::read_sun() {
  const Object* location = nullptr;
  const Object* run = nullptr;
  const Object* timestep = nullptr;
  for (const Object& o : objects_) {
    const std::string cls = o.spec->name;
    if (cls == "Site:Location" && location == nullptr) location = &o;
    if (cls == "Timestep" && timestep == nullptr) timestep = &o;
    if (cls == "RunPeriod") {
      if (run == nullptr)
        run = &o;
      else
        warnings_.push_back({{file_, o.place}, "a second RunPeriod: the sun follows the first one only"});
    }
  }
  if (location == nullptr) return std::nullopt;
  SunPeriod sun;
  auto in_range = [&](const Object& o, const char* key, double lo, double hi, double fallback) {
    const Value& v = field(o, key);
    const double x = number(v).value_or(fallback);
    if (x < lo || x > hi)
      fail(v.place, "out of range [" + detail::format_number(lo) + ", " + detail::format_number(hi) + "]: " +
                        detail::format_number(x));
    return x;
  };
  sun.site.latitude = in_range(*location, "latitude", -90, 90, 0);
  sun.site.longitude = in_range(*location, "longitude", -180, 180, 0);
  sun.utc_offset_hours = in_range(*location, "time_zone", -12, 14, 0);
  sun.site.elevation = in_range(*location, "elevation", -300, 8900, 0);
  sun.north_axis = north_axis_;
  // A RunPeriod without years runs in a non-leap year; 2023 starts on a Sunday, EnergyPlus's
  // default first day of the week.
  constexpr int default_year = 2023;
  int begin_month = 1, begin_day = 1, end_month = 12, end_day = 31;
  int begin_year = default_year;
  std::optional<int> end_year;
  const Object* dates = run;
  if (dates != nullptr) {
    auto whole = [&](const char* key, int fallback, int lo, int hi) {
      const Value& v = field(*dates, key);
      const std::optional<double> x = number(v);
      if (!x) return fallback;
      if (*x != std::floor(*x) || *x < lo || *x > hi)
        fail(v.place, "expected a whole number in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], not " +
                          detail::format_number(*x));
      return static_cast<int>(*x);
    };
    begin_month = whole("begin_month", 1, 1, 12);
    begin_day = whole("begin_day_of_month", 1, 1, 31);
    end_month = whole("end_month", 12, 1, 12);
    end_day = whole("end_day_of_month", 31, 1, 31);
    begin_year = whole("begin_year", default_year, 1, 9999);
    if (number(field(*dates, "end_year"))) end_year = whole("end_year", default_year, 1, 9999);
  } else {
    warnings_.push_back({{file_, location->place}, "no RunPeriod: the sun covers the whole of " +
                                                       std::to_string(default_year)});
  }
  // A period that ends before it begins in the year runs on into the next year (EnergyPlus).
  const int last_year = end_year ? *end_year
                                 : (end_month * 100 + end_day < begin_month * 100 + begin_day ? begin_year + 1 : begin_year);
  auto date = [&](int y, int m, int d, const char* key) {
    static const int days[12] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
    const int in_month = days[m - 1] + (m == 2 && is_leap(y) ? 1 : 0);
    if (d > in_month)
      fail(field(*dates, key).place, "day " + std::to_string(d) + " is not in month " + std::to_string(m) +
                                         " of " + std::to_string(y));
    char text[16];
    std::snprintf(text, sizeof text, "%04d-%02d-%02d", y, m, d);
    return std::string(text);
  };
  sun.start = date(begin_year, begin_month, begin_day, "begin_day_of_month");
  sun.end = date(last_year, end_month, end_day, "end_day_of_month");
  if (sun.end < sun.start)
    fail(dates != nullptr ? dates->place : location->place, "the run period ends (" + sun.end + ") before it begins (" +
                                                               sun.start + ")");
  int per_hour = 6;  // EnergyPlus's default Timestep
  if (timestep != nullptr) {
    const Value& v = field(*timestep, "number_of_timesteps_per_hour");
    const std::optional<double> x = number(v);
    if (x) {
      if (*x != std::floor(*x) || *x < 1 || *x > 60 || 60 % static_cast<int>(*x) != 0)
        fail(v.place, "expected a divisor of 60 (1, 2, 3, 4, 5, 6, 10, 12, 15, 20, 30, 60), not " +
                          detail::format_number(*x));
      per_hour = static_cast<int>(*x);
    }
  }
  sun.step_minutes = 60 / per_hour;
  return sun;
}

Model Reader::read(const std::string& text, bool epjson) {
  if (epjson)
    load_epjson(text);
  else
    load_idf(text);
  read_globals();
  read_surfaces();
  Model model;
  cut_and_emit(model);
  model.sun = read_sun();
  // Classes without geometry (constructions, schedules, HVAC...) are skipped without a word: a
  // model holds dozens. Geometry classes this reader does not build are named.
  for (const auto& ignored : ignored_) {
    const std::string& key = ignored.first;
    const auto& entry = ignored.second;
    const bool geometry = std::any_of(unsupported_geometry_classes().begin(), unsupported_geometry_classes().end(),
                                      [&](const std::string& c) { return same_text(c, key); });
    if (geometry)
      warnings_.push_back({{file_, entry.second},
                           std::to_string(entry.first) + " object(s) not read: this reader does not build " +
                               entry.second + " geometry, so it is missing from the scene (docs/energyplus.md)"});
  }
  if (model.faces.empty())
    fail("", "no exterior surface or shading surface found (BuildingSurface:Detailed, "
             "FenestrationSurface:Detailed, Shading:*:Detailed, ...)");
  model.warnings = std::move(warnings_);
  return model;
}

}  // namespace

bool is_energyplus_file_name(const std::filesystem::path& file) {
  const std::string ext = lower(file.extension().string());
  return ext == ".idf" || ext == ".epjson";
}

Model parse_energyplus(const std::string& text, const std::string& display_name, bool epjson,
                       const LoadOptions& options) {
  Reader reader(display_name, options);
  // A UTF-8 byte order mark (Windows editors write one) is not part of the first class name.
  const bool bom = text.compare(0, 3, "\xEF\xBB\xBF") == 0;
  try {
    return reader.read(bom ? text.substr(3) : text, epjson);
  } catch (const nlohmann::json::exception& e) {
    // A JSON type the reader did not expect somewhere: still one line naming the file.
    throw InputError({display_name, ""}, "unexpected JSON: " + json_exception_reason(e.what()));
  }
}

Model read_energyplus(const std::filesystem::path& file, const std::string& display_name,
                      const LoadOptions& options) {
  const std::string text = read_input_file(file, display_name, options.max_file_bytes);
  bool epjson = lower(file.extension().string()) == ".epjson";
  if (!epjson) {
    const std::size_t first = text.find_first_not_of(" \t\r\n\xEF\xBB\xBF");
    epjson = first != std::string::npos && text[first] == '{';
  }
  return parse_energyplus(text, display_name, epjson, options);
}

}  // namespace shadow::scene_readers
