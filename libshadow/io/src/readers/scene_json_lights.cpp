// SPDX-License-Identifier: GPL-3.0-or-later
// The scene reader's lights (scene/scene_json_reader.hpp): point, directional, area and sun
// lights, and the `sun` entry that lights the scene by a place and dates.
#include "readers/scene_json_reader.hpp"

#include "core/lights.hpp"
#include "core/polygon_holes.hpp"
#include "readers/json_document.hpp"
#include "readers/model_dispatch.hpp"
#include "readers/obj_reader.hpp"
#include "validation/planarity.hpp"

#include <shadow/input_file.hpp>
#include <shadow/scene_io.hpp>
#include <shadow/sun.hpp>

#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace shadow::scene_json {

void SceneReader::read_lights(const Json& lights, bool may_be_empty) {
  require_array(lights, "lights");
  if (lights.empty() && !may_be_empty)
    fail("lights", "the scene has no lights; at least one is needed (or a \"sun\" block)");
  std::map<std::string, std::size_t> seen;
  const std::vector<std::string> types = {"directional", "point", "area", "disk"};
  for (std::size_t i = 0; i < lights.size(); ++i) {
    const std::string path = element("lights", i);
    const Json& l = lights[i];
    require_object(l, path, "a light");
    // An unknown type first: its keys would otherwise be reported as unknown keys.
    const Json* type = find(l, "type");
    if (type != nullptr && !type->is_string())
      fail(member(path, "type"), "expected \"directional\", \"point\", \"area\" or \"disk\", got " +
                                     describe(*type));
    if (type != nullptr && std::find(types.begin(), types.end(), type->get<std::string>()) == types.end())
      fail(member(path, "type"), "unknown light type " + quote(type->get<std::string>()) +
                                     suggestion(type->get<std::string>(), types) +
                                     "; known types: \"directional\", \"point\", \"area\", \"disk\"");
    check_keys(l, path, {"name", "type", "to_light", "position", "intensity", "color", "polygon", "normal",
                         "radius", "angular_diameter"});
    Light light;
    light.name = get_name(l, path, "each light needs a unique name");
    if (const auto [it, inserted] = seen.emplace(light.name, i); !inserted)
      fail(member(path, "name"), "light name " + quote(light.name) + " is already used by " +
                                     element("lights", it->second));
    if (type == nullptr) fail(path, "missing \"type\" (\"directional\", \"point\", \"area\" or \"disk\")");
    const std::string kind = type->get<std::string>();
    const Json* to_light = find(l, "to_light");
    const Json* position = find(l, "position");
    // Keys that belong to other kinds of light: named, with what the kind takes instead.
    auto refuse = [&](const char* key, const std::string& instead) {
      if (find(l, key) != nullptr)
        fail(member(path, key), "a" + std::string(kind == "area" ? "n " : " ") + kind + " light has no \"" + key +
                                    "\"; " + instead);
    };
    if (kind != "directional") refuse("angular_diameter", "only a directional light (the sun's disk) has one");
    if (kind != "area") refuse("polygon", "only an area light has one");
    if (kind != "disk") {
      refuse("normal", "only a disk light has one");
      refuse("radius", "only a disk light has one");
    }
    if (kind == "directional") {
      light.type = LightType::Directional;
      if (position != nullptr)
        fail(member(path, "position"),
             "a directional light has no position; give \"to_light\", the direction toward the light");
      if (to_light == nullptr)
        fail(path, "missing \"to_light\" (the direction from the scene toward the light)");
      light.to_light = get_vec3(*to_light, member(path, "to_light"));
      if (light.to_light == glm::dvec3(0.0))
        fail(member(path, "to_light"), "direction has zero length");
      if (const Json* d = find(l, "angular_diameter")) {
        light.angular_diameter = get_number(*d, member(path, "angular_diameter"));
        if (light.angular_diameter < 0 || light.angular_diameter > detail::max_angular_diameter)
          fail(member(path, "angular_diameter"),
               "angular_diameter must be in [0, " + format_number(detail::max_angular_diameter) +
                   "] degrees (0: a point sun; the sun's disk is about 0.53), got " +
                   format_number(light.angular_diameter));
      }
    } else if (kind == "point") {
      light.type = LightType::Point;
      if (to_light != nullptr)
        fail(member(path, "to_light"),
             "a point light has no \"to_light\" direction; give its \"position\"");
      if (position == nullptr) fail(path, "missing \"position\" (where the point light is)");
      light.position = get_vec3(*position, member(path, "position"));
    } else if (kind == "area") {
      light.type = LightType::Area;
      if (to_light != nullptr)
        fail(member(path, "to_light"), "an area light has no \"to_light\"; its \"polygon\" says where it is");
      if (position != nullptr)
        fail(member(path, "position"), "an area light has no \"position\"; its \"polygon\" says where it is");
      const Json* polygon = find(l, "polygon");
      if (polygon == nullptr)
        fail(path, "missing \"polygon\" (the luminous polygon, [[x, y, z], ...], counter-clockwise seen from "
                   "the side it lights)");
      const std::string polygon_path = member(path, "polygon");
      require_array(*polygon, polygon_path);
      for (std::size_t k = 0; k < polygon->size(); ++k)
        light.polygon.push_back(get_vec3((*polygon)[k], element(polygon_path, k)));
      detail::check_area_polygon(light.polygon, file_, polygon_path);
    } else {
      light.type = LightType::Disk;
      if (to_light != nullptr)
        fail(member(path, "to_light"), "a disk light has no \"to_light\"; give its \"normal\", the side it lights");
      if (position == nullptr) fail(path, "missing \"position\" (the disk's centre)");
      light.position = get_vec3(*position, member(path, "position"));
      const Json* normal = find(l, "normal");
      if (normal == nullptr) fail(path, "missing \"normal\" (the side the disk lights)");
      light.normal = get_vec3(*normal, member(path, "normal"));
      if (light.normal == glm::dvec3(0.0)) fail(member(path, "normal"), "normal has zero length");
      const Json* radius = find(l, "radius");
      if (radius == nullptr) fail(path, "missing \"radius\" (the disk's radius)");
      light.radius = get_number(*radius, member(path, "radius"));
      if (!(light.radius > 0)) fail(member(path, "radius"), "radius must be > 0, got " + format_number(light.radius));
    }
    if (const Json* intensity = find(l, "intensity")) {
      light.intensity = get_number(*intensity, member(path, "intensity"));
      if (light.intensity < 0)
        fail(member(path, "intensity"), "intensity must be >= 0, got " + format_number(light.intensity));
    }
    if (const Json* color = find(l, "color")) light.color = get_color(*color, member(path, "color"));
    scene_.lights.push_back(std::move(light));
  }
}

std::optional<std::string> local_time_doubt(const SunPeriod& period, bool offset_given) {
  if (!period.times.empty()) return std::nullopt;  // explicit times carry their own zone, mostly
  // Local standard time is within some 3 hours of the sun's (Kashgar, on Beijing's UTC+8 at 76 E,
  // is 2.9 h off); more is most often a forgotten or mistyped zone, which shifts every instant.
  const double solar = period.site.longitude / 15.0;
  double off = std::fmod(period.utc_offset_hours - solar, 24.0);
  if (off > 12.0) off -= 24.0;
  if (off < -12.0) off += 24.0;
  if (std::abs(off) <= 3.5) return std::nullopt;
  char text[320];
  std::snprintf(text, sizeof text,
                "%s UTC%+g h is %.1f h from the sun's time at longitude %g (about UTC%+.1f): the period's dates "
                "and hours are local standard time in UTC%+g; set \"time_zone\" or \"utc_offset\" if that is not "
                "the site's",
                offset_given ? "the local time" : "no \"time_zone\" or \"utc_offset\": the local time",
                period.utc_offset_hours, std::abs(off), period.site.longitude, solar, period.utc_offset_hours);
  return std::string(text);
}

SunPeriod SceneReader::read_sun(const Json& sun) const {
  require_object(sun, "sun", "the sun block");
  check_keys(sun, "sun", {"latitude", "longitude", "elevation", "pressure", "temperature", "utc_offset",
                          "time_zone", "start", "end", "step_minutes", "times", "north_axis",
                          "min_elevation", "delta_t", "angular_diameter", "energyplus_times"});
  SunPeriod period;
  period.site.latitude = get_number(require(sun, "sun", "latitude", "degrees, north positive"), "sun.latitude");
  period.site.longitude = get_number(require(sun, "sun", "longitude", "degrees, east positive"), "sun.longitude");
  const std::pair<const char*, double*> numbers[] = {
      {"elevation", &period.site.elevation}, {"pressure", &period.site.pressure},
      {"temperature", &period.site.temperature}, {"north_axis", &period.north_axis},
      {"min_elevation", &period.min_elevation}, {"delta_t", &period.delta_t},
      {"angular_diameter", &period.angular_diameter}};
  for (const auto& [key, target] : numbers)
    if (const Json* value = find(sun, key)) *target = get_number(*value, member("sun", key));
  const Json* offset = find(sun, "utc_offset");
  const Json* zone = find(sun, "time_zone");
  if (offset != nullptr && zone != nullptr)
    fail("sun", "give either \"utc_offset\" or \"time_zone\", not both");
  if (offset != nullptr) period.utc_offset_hours = get_number(*offset, "sun.utc_offset");
  if (zone != nullptr) {
    if (!zone->is_string()) fail("sun.time_zone", "expected a string like \"UTC+05:30\", got " + describe(*zone));
    period.time_zone = zone->get<std::string>();
    const std::optional<int> minutes = parse_utc_offset(period.time_zone);
    if (!minutes)
      fail("sun.time_zone",
           "unknown time zone " + quote(period.time_zone) +
               "; give \"UTC\", \"UTC+hh:mm\" or \"UTC-hh:mm\" (local standard time, no daylight saving), "
               "or \"utc_offset\" in hours; zone names such as \"Europe/Paris\" are not read (their offset "
               "changes with daylight saving)");
    period.utc_offset_hours = *minutes / 60.0;
  }
  auto date = [&](const char* key, std::string& out) {
    if (const Json* value = find(sun, key)) {
      if (!value->is_string()) fail(member("sun", key), "expected a date \"YYYY-MM-DD\", got " + describe(*value));
      out = value->get<std::string>();
      if (out.empty()) fail(member("sun", key), "expected a date \"YYYY-MM-DD\", got an empty string");
    }
  };
  date("start", period.start);
  date("end", period.end);
  if (const Json* step = find(sun, "step_minutes")) {
    if (!step->is_number_integer())
      fail("sun.step_minutes", "expected a whole number of minutes, got " + describe(*step));
    const auto minutes = step->get<std::int64_t>();
    if (minutes <= 0 || minutes > 1440 || 1440 % minutes != 0)
      fail("sun.step_minutes", "step_minutes must divide a day (1440 minutes: 1, 5, 10, 15, 30, 60, 120, ...), got " +
                                   std::to_string(minutes));
    period.step_minutes = static_cast<int>(minutes);
    if (find(sun, "times") != nullptr) fail("sun", "\"step_minutes\" belongs to a period; with \"times\" leave it out");
  }
  if (const Json* ep = find(sun, "energyplus_times")) {
    if (!ep->is_boolean()) fail("sun.energyplus_times", "expected true or false, got " + describe(*ep));
    if (find(sun, "times") != nullptr) fail("sun", "\"energyplus_times\" belongs to a period; with \"times\" leave it out");
    period.energyplus_times = ep->get<bool>();
  }
  if (const Json* times = find(sun, "times")) {
    require_array(*times, "sun.times");
    if (times->empty()) fail("sun.times", "no times; give at least one (or a period)");
    if (times->size() > max_sun_instants)
      fail("sun.times", std::to_string(times->size()) + " times; at most " + std::to_string(max_sun_instants) +
                            " are allowed");
    // A time without Z or an offset is local standard time (utc_offset), like the period's dates.
    const double offset_minutes = period.utc_offset_hours * 60.0;
    const int local = std::abs(offset_minutes) <= 14 * 60 ? static_cast<int>(std::lround(offset_minutes)) : 0;
    for (std::size_t i = 0; i < times->size(); ++i) {
      const Json& t = (*times)[i];
      const std::string path = element("sun.times", i);
      if (!t.is_string()) fail(path, "expected an ISO 8601 time \"YYYY-MM-DDThh:mm:ssZ\", got " + describe(t));
      const std::optional<UtcSeconds> utc = parse_iso8601(t.get_ref<const std::string&>(), local);
      if (!utc)
        fail(path, "expected an ISO 8601 time that exists, \"YYYY-MM-DDThh:mm:ss\" with \"Z\", \"+hh:mm\" or "
                   "nothing (local standard time), got " + describe(t));
      period.times.push_back(*utc);
    }
  }
  check_sun_period(period, file_, "sun");
  return period;
}

}  // namespace shadow::scene_json
