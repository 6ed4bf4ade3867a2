// SPDX-License-Identifier: GPL-3.0-or-later
// EnergyPlus geometry in: IDF and epJSON become one list of objects with positional fields (the
// IDD's order), each field knowing where it was written; the geometry is then built once for
// both syntaxes, so an IDF and its epJSON twin give the same faces bit for bit.
#include "readers/energyplus_reader.hpp"
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


namespace shadow::scene_readers {
namespace energyplus {

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

namespace {

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

/// "9.6", "24.1.0" -> major * 100 + minor (energyplus_version_code); a blank field or a major
/// beyond 999 (no EnergyPlus version) leaves `fallback`, the current field lists. Text that is no
/// version is an error at `place`: read with the wrong field lists, every surface would be misread.
int parse_version(const std::string& text, int fallback, const std::string& file, const std::string& place) {
  if (text.empty()) return fallback;  // left blank: the current field lists
  if (!is_version_text(text))
    throw InputError({file, place}, "expected an EnergyPlus version like 24.1 or 9.6, not " +
                                        json_string(text));
  const int code = energyplus_version_code(text);
  return code == 0 ? fallback : code;
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

}  // namespace

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


void Reader::read_globals() {
  double appendix_g_rotation = 0.0;
  for (const Object& o : objects_) {
    const std::string cls = o.spec->name;
    if (cls == "GlobalGeometryRules") {
      const Value& direction = field(o, "vertex_entry_direction");
      const Value& corner = field(o, "starting_vertex_position");
      const char* const corners[] = {"UpperLeftCorner", "LowerLeftCorner", "LowerRightCorner", "UpperRightCorner"};
      for (int c = 0; c < 4; ++c)
        if (same_text(corner.text, corners[c])) start_corner_ = c;
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
      north_axis_ = building_north_ = number_or(o, "north_axis", 0.0);
    } else if (cls == "Compliance:Building") {
      appendix_g_rotation = number_or(o, "building_rotation_for_appendix_g", 0.0);
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
                           std::string("world coordinates: Building North Axis, zone origins and zone directions of "
                                       "relative north are ignored, as EnergyPlus does") +
                               (rectangular_world_ ? "" : " (but for the simple rectangular surfaces: with Rectangular "
                                                          "Surface Coordinate System Relative EnergyPlus places their "
                                                          "corners through them)")});
    north_axis_ = 0.0;
  }
  // Compliance:Building's rotation for ASHRAE 90.1 Appendix G turns every vertex, in world
  // coordinates too (where it is the only turn), after the Building North Axis: EnergyPlus's
  // building rotation is their sum. Site shading in relative coordinates stays where it is, as
  // for the north axis (world_to_model turns it back by the sum).
  north_axis_ += appendix_g_rotation;
  appendix_g_ = appendix_g_rotation;
}

namespace {

bool is_leap(int y) { return is_valid_date(y, 2, 29); }  // shadow/sun.hpp's calendar

}  // namespace

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
  // No Timestep object: EnergyPlus takes 4 steps an hour ("Number of TimeSteps in Hour
  // defaulted to 4"); the object with its field blank: the field's default, 6.
  int per_hour = timestep == nullptr ? 4 : 6;
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
  sun.energyplus_times = true;  // each step's sun where EnergyPlus takes it
  // Read from EnergyPlus's ScheduleManager.cc, not run: LookUpScheduleValue adds the daylight
  // saving indicator to the hour of every schedule it reads, the imported shading file's too,
  // whose rows are in standard time (as libshadow writes them and EnergyPlus exports them).
  if (const auto dst = ignored_.find("runperiodcontrol:daylightsavingtime"); dst != ignored_.end())
    warnings_.push_back({{file_, dst->second.second},
                         "the model has daylight saving time: EnergyPlus reads schedules one hour later while it is "
                         "on, so a run importing energyplus-shading.csv (rows in standard time) would take each "
                         "hour's shading from the next hour's row then; remove RunPeriodControl:DaylightSavingTime "
                         "for that run"});
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

}  // namespace energyplus

using energyplus::lower;
using energyplus::Reader;

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

int energyplus_version_code(std::string_view text) {
  if (!energyplus::is_version_text(text)) return 0;
  int major = 0, minor = 0;
  const char* end = text.data() + text.size();
  const auto [after_major, e1] = std::from_chars(text.data(), end, major);
  if (e1 != std::errc() || major < 1 || major > 999) return 0;
  if (after_major < end && *after_major == '.') {
    const auto [after_minor, e2] = std::from_chars(after_major + 1, end, minor);
    if (e2 != std::errc() || minor < 0 || minor > 99) minor = 0;
  }
  return major * 100 + minor;
}

}  // namespace shadow::scene_readers
