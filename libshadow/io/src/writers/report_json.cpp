// SPDX-License-Identifier: GPL-3.0-or-later
#include "runtime/parallel.hpp"
#include "writers/face_identity_json.hpp"
#include "writers/json_text.hpp"
#include "writers/names.hpp"

#include <shadow/output.hpp>
#include <shadow/sun.hpp>
#include <shadow/version.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <exception>
#include <map>
#include <string>
#include <thread>
#include <vector>

namespace shadow {
namespace {

// ordered_json keeps keys in the order written here, which reads better than alphabetical.
using Json = nlohmann::ordered_json;

Json vec3(const glm::dvec3& v) { return Json::array({v.x, v.y, v.z}); }

/// Neumaier's compensated sum: totals over millions of faces keep the digits of their parts.
class Sum {
 public:
  void add(double x) {
    const double t = sum_ + x;
    compensation_ += std::abs(sum_) >= std::abs(x) ? (sum_ - t) + x : (x - t) + sum_;
    sum_ = t;
  }
  [[nodiscard]] double value() const { return sum_ + compensation_; }

 private:
  double sum_ = 0.0;
  double compensation_ = 0.0;
};

Json lights_json(const Scene& scene) {
  Json lights = Json::array();
  for (std::size_t i = 0; i < scene.lights.size(); ++i) {
    const Light& light = scene.lights[i];
    Json entry = {{"id", i}, {"name", light.name}};
    if (light.type == LightType::Directional) {
      entry["type"] = "directional";
      entry["to_light"] = vec3(light.to_light);
      if (light.angular_diameter > 0) entry["angular_diameter"] = light.angular_diameter;
    } else if (light.type == LightType::Area) {
      entry["type"] = "area";
      Json polygon = Json::array();
      for (const glm::dvec3& v : light.polygon) polygon.push_back(vec3(v));
      entry["polygon"] = std::move(polygon);
    } else if (light.type == LightType::Disk) {
      entry["type"] = "disk";
      entry["position"] = vec3(light.position);
      entry["normal"] = vec3(light.normal);
      entry["radius"] = light.radius;
    } else {
      entry["type"] = "point";
      entry["position"] = vec3(light.position);
    }
    entry["intensity"] = light.intensity;
    entry["color"] = vec3(light.color);
    lights.push_back(std::move(entry));
  }
  // A sun's light also says when it shines and where the sun stands (additive keys).
  for (const SunInstant& instant : scene.sun_instants) {
    if (instant.light_id >= lights.size()) continue;
    Json& entry = lights[instant.light_id];
    entry["time"] = format_iso8601_utc(instant.time);
    entry["elevation"] = instant.position.elevation;
    entry["azimuth"] = instant.position.azimuth;
  }
  return lights;
}

/// The scene's `sun` block as it was read, with the count of its instants above and below the
/// horizon (below: at or under min_elevation, no light).
Json sun_json(const Scene& scene) {
  const SunPeriod& sun = *scene.sun;
  Json j;
  j["site"] = {{"latitude", sun.site.latitude},
               {"longitude", sun.site.longitude},
               {"elevation", sun.site.elevation},
               {"pressure", sun.site.pressure},
               {"temperature", sun.site.temperature}};
  if (sun.times.empty()) {
    j["period"] = {{"start", sun.start}, {"end", sun.end}, {"step_minutes", sun.step_minutes}};
    if (sun.energyplus_times) j["period"]["energyplus_times"] = true;
  } else {
    Json times = Json::array();
    for (const UtcSeconds t : sun.times) times.push_back(format_iso8601_utc(t));
    j["times"] = std::move(times);
  }
  j["utc_offset"] = sun.utc_offset_hours;
  if (!sun.time_zone.empty()) j["time_zone"] = sun.time_zone;
  j["north_axis"] = sun.north_axis;
  j["min_elevation"] = sun.min_elevation;
  if (sun.angular_diameter > 0) j["angular_diameter"] = sun.angular_diameter;  // additive key
  j["delta_t"] = sun.delta_t;
  std::size_t above = 0;
  for (const SunInstant& instant : scene.sun_instants) above += instant.light_id != SunInstant::none ? 1 : 0;
  j["instants"] = scene.sun_instants.size();
  j["above_horizon"] = above;
  j["below_horizon"] = scene.sun_instants.size() - above;
  return j;
}

/// A number as nlohmann's serializer writes it (its shortest round-trip form, `null` when not
/// finite), appended without building a value.
void append_number(std::string& out, double x) {
  if (!std::isfinite(x)) {
    out += "null";
    return;
  }
  char buffer[64];
  // A whole number below 1e15 (a normal's 0 and 1, an axis-aligned face's azimuth and tilt, a
  // shadowed face's lit area): nlohmann writes its digits and ".0" (-0.0 too), written here
  // without its shortest-digits search, which took a sixth of a million faces' report.
  if (std::fabs(x) < 1e15 && x == std::trunc(x)) {
    char* end = buffer;
    if (std::signbit(x)) *end++ = '-';
    end = std::to_chars(end, buffer + sizeof buffer, static_cast<long long>(std::fabs(x))).ptr;
    *end++ = '.';
    *end++ = '0';
    out.append(buffer, static_cast<std::size_t>(end - buffer));
    return;
  }
  char* end = nlohmann::detail::to_chars(buffer, buffer + sizeof buffer, x);
  out.append(buffer, static_cast<std::size_t>(end - buffer));
}

/// A JSON string as nlohmann writes it (escapes, bytes that are not UTF-8 replaced): printable
/// ASCII without quote or backslash is copied as is, anything else goes through nlohmann.
void append_string(std::string& out, const std::string& text) {
  const bool plain = std::all_of(text.begin(), text.end(), [](char c) {
    return c >= 0x20 && c < 0x7f && c != '"' && c != '\\';
  });
  if (plain) {
    out += '"';
    out += text;
    out += '"';
  } else {
    out += Json(text).dump(-1, ' ', false, Json::error_handler_t::replace);
  }
}

/// What face entries share: each light's and mesh's name as JSON text, made once.
struct EntryNames {
  std::vector<std::string> lights;  ///< by light id; ids past the scene's are made when met
  std::vector<std::string> meshes;  ///< by mesh id
  EntryNames(const Scene& scene, std::size_t light_ids) {
    for (std::size_t l = 0; l < light_ids; ++l) {
      lights.emplace_back();
      append_string(lights.back(), detail::light_display_name(scene, l));
    }
    for (const Mesh& mesh : scene.meshes) {
      meshes.emplace_back();
      append_string(meshes.back(), mesh.name);
    }
  }
};

/// Appends face `face_id`'s report entry from its FaceLighting entries (all for `face_id`), as
/// the faces array holds it (4 spaces in, 2 more a level): the text nlohmann's dump(2) gives for
/// the whole document, written directly (a million faces' entries built as values and dumped
/// took most of a report's time). Keys in this order; those after `faces_light` are additive.
void append_face_entry(std::string& out, const Scene& scene, const EntryNames& names, std::size_t face_id,
                       const std::vector<const FaceLighting*>& entries, bool fast) {
  auto member = [&out](const char* indent_and_key) { out += indent_and_key; };
  out += "{\n      \"id\": ";
  out += std::to_string(face_id);
  member(",\n      \"mesh\": ");
  const std::size_t mesh = face_id < scene.faces.size() ? scene.faces[face_id].mesh : scene.meshes.size();
  out += mesh < names.meshes.size() ? names.meshes[mesh] : std::string("\"\"");
  if (face_id < scene.faces.size()) {
    const Face& face = scene.faces[face_id];
    const detail::FaceOrientation o = detail::face_orientation(face, detail::north_axis_of(scene));
    member(",\n      \"name\": ");
    append_string(out, face.name);
    member(",\n      \"source\": ");
    append_string(out, face.source.to_string());
    if (!face.kind.empty()) {
      member(",\n      \"kind\": ");
      append_string(out, face.kind);
    }
    member(",\n      \"normal\": [\n        ");
    append_number(out, o.normal.x);
    out += ",\n        ";
    append_number(out, o.normal.y);
    out += ",\n        ";
    append_number(out, o.normal.z);
    member("\n      ],\n      \"azimuth\": ");
    append_number(out, o.azimuth);
    member(",\n      \"tilt\": ");
    append_number(out, o.tilt);
  }
  member(",\n      \"area\": ");
  append_number(out, entries.front()->area);
  member(",\n      \"lights\": [");
  for (std::size_t i = 0; i < entries.size(); ++i) {
    const FaceLighting& e = *entries[i];
    out += i == 0 ? "\n        {\n          \"light\": " : ",\n        {\n          \"light\": ";
    out += std::to_string(e.light_id);
    member(",\n          \"light_name\": ");
    if (e.light_id < names.lights.size()) out += names.lights[e.light_id];
    else append_string(out, detail::light_display_name(scene, e.light_id));
    member(",\n          \"lit_area\": ");
    append_number(out, e.lit_area);
    member(",\n          \"shadow_area\": ");
    append_number(out, e.shadow_area);
    member(",\n          \"lit_fraction\": ");
    append_number(out, e.lit_fraction);
    member(e.faces_light ? ",\n          \"faces_light\": true" : ",\n          \"faces_light\": false");
    // The fast path's certificate: |lit_area - exact lit area| <= this.
    if (fast) {
      member(",\n          \"lit_area_error_bound\": ");
      append_number(out, e.lit_area_error_bound);
    }
    // Cells too thin to be written as double polygons (only when there are some).
    if (e.dropped_area > 0) {
      member(",\n          \"dropped_area\": ");
      append_number(out, e.dropped_area);
    }
    // An extended light's exact regions (docs/area-lights.md).
    if (e.light_id < scene.lights.size() && scene.lights[e.light_id].is_extended()) {
      member(",\n          \"fully_lit_area\": ");
      append_number(out, e.fully_lit_area);
      member(",\n          \"penumbra_area\": ");
      append_number(out, e.penumbra_area);
      member(",\n          \"umbra_area\": ");
      append_number(out, e.umbra_area);
    }
    out += "\n        }";
  }
  out += "\n      ]\n    }";
}

std::string dump(const Json& value, int indent = -1) { return detail::dump_json(value, indent); }

Json run_json(const Scene& scene, const ShadowResult& result, const RunInfo* run) {
  Json j;
  j["scene"] = run != nullptr && !run->scene.empty() ? run->scene : scene.source.string();
  j["started_utc"] = run != nullptr && !run->started_utc.empty() ? Json(run->started_utc) : Json(nullptr);
  j["libshadow_version"] = version();
  j["arithmetic"] = result.arithmetic == Arithmetic::Fast ? "fast" : "exact";
  if (run != nullptr) {
    const ShadowOptions& o = run->options;
    j["options"] = {{"threads", o.threads},
                    {"polygons", o.polygons},
                    {"planes", o.planes},
                    {"plane_window", o.plane_window},
                    {"lights", o.lights},
                    {"arithmetic", o.arithmetic == Arithmetic::Fast ? "fast" : "exact"},
                    {"planarity_tolerance", run->planarity_tolerance}};
    // Additive keys, written only when not the defaults (earlier reports stay as they were).
    const ShadowOptions defaults;
    if (o.tile_casters != defaults.tile_casters) j["options"]["tile_casters"] = o.tile_casters;
    if (o.fast_tile_casters != defaults.fast_tile_casters) j["options"]["fast_tile_casters"] = o.fast_tile_casters;
  }
  return j;
}

void write_report(std::ostream& out, const Scene& scene, const ShadowResult& result, const RunInfo* run);

}  // namespace

void write_report_json(std::ostream& out, const Scene& scene, const ShadowResult& result) {
  write_report(out, scene, result, nullptr);
}

void write_report_json(std::ostream& out, const Scene& scene, const ShadowResult& result,
                       const RunInfo& run) {
  write_report(out, scene, result, &run);
}

namespace {

/// The faces array's entries, `group_start` giving each face's first entry (then
/// entries.size()): made on every thread (a million faces: most of the report's time), a window
/// of blocks at a time so that the text held stays small, and written in face order: the same
/// bytes whatever the thread count. From two threads on, a writer thread writes a window while
/// every thread of the run makes the next; two windows of text are held, the one made and the
/// one written. (The writer was once one of the run's threads, leaving a single maker on two:
/// a million faces' 560 MB of text took 0.5 s to make while the writer, mostly the kernel's
/// copy into the page cache, sat nearly idle.)
void write_face_entries(std::ostream& out, const Scene& scene, const std::vector<const FaceLighting*>& entries,
                        const std::vector<std::size_t>& group_start, bool fast, unsigned requested_threads) {
  const std::size_t receiving_faces = group_start.size() - 1;
  const unsigned threads = runtime::resolve_threads(requested_threads);
  const EntryNames names(scene, scene.lights.size());
  constexpr std::size_t kFacesPerBlock = 1024;
  const std::size_t blocks = (receiving_faces + kFacesPerBlock - 1) / kFacesPerBlock;
  const std::size_t window = std::min<std::size_t>(blocks, std::size_t{4} * threads);
  std::vector<std::string> made(window), written(window);
  auto make = [&](std::size_t first, std::size_t count) {
    runtime::parallel_for(count, static_cast<unsigned>(std::min<std::size_t>(threads, count)), [&](unsigned, std::size_t k) {
      std::string& text = made[k];
      text.clear();
      std::vector<const FaceLighting*> group;
      const std::size_t end = std::min(receiving_faces, (first + k + 1) * kFacesPerBlock);
      for (std::size_t g = (first + k) * kFacesPerBlock; g < end; ++g) {
        group.assign(entries.begin() + static_cast<std::ptrdiff_t>(group_start[g]),
                     entries.begin() + static_cast<std::ptrdiff_t>(group_start[g + 1]));
        text += g == 0 ? "\n    " : ",\n    ";
        append_face_entry(text, scene, names, group.front()->face_id, group, fast);
      }
    });
  };
  // From two threads on, `written` goes to the writer thread, which alone touches `out` until it
  // is joined: before the next hand-over, and before an exception from making leaves (a joinable
  // std::thread may not be destroyed). On one thread this thread writes. A stream whose
  // exceptions() are set throws while writing: caught there and rethrown after the join, as it
  // would have come from a write on this thread.
  std::thread writer;
  std::exception_ptr write_error;
  struct JoinOnExit {
    std::thread& thread;
    ~JoinOnExit() {
      if (thread.joinable()) thread.join();
    }
  } join_on_exit{writer};
  auto finish_writing = [&] {
    if (writer.joinable()) writer.join();
    if (write_error) std::rethrow_exception(write_error);
  };
  for (std::size_t first = 0; first < blocks; first += window) {
    const std::size_t count = std::min(window, blocks - first);
    make(first, count);
    finish_writing();
    made.swap(written);
    auto write = [&out, &written, &write_error, count] {
      try {
        for (std::size_t k = 0; k < count; ++k) out << written[k];
      } catch (...) {
        write_error = std::current_exception();
      }
    };
    if (threads == 1)
      write();
    else
      writer = std::thread(write);
  }
  finish_writing();
}

void write_report(std::ostream& out, const Scene& scene, const ShadowResult& result, const RunInfo* run) {
  // Entries by face then light, whatever order they came in (the engine already sorts them).
  std::vector<const FaceLighting*> entries;
  entries.reserve(result.lighting.size());
  for (const FaceLighting& e : result.lighting) entries.push_back(&e);
  auto by_face_light = [](const FaceLighting* a, const FaceLighting* b) {
    return a->face_id != b->face_id ? a->face_id < b->face_id : a->light_id < b->light_id;
  };
  if (!std::is_sorted(entries.begin(), entries.end(), by_face_light))
    std::stable_sort(entries.begin(), entries.end(), by_face_light);

  struct LightTotals {
    Sum area;
    Sum lit_area;
    Sum bound;
  };
  const bool fast = result.arithmetic == Arithmetic::Fast;
  std::map<std::size_t, LightTotals> per_light;
  std::map<std::pair<std::size_t, std::size_t>, LightTotals> per_mesh;  // (mesh, light)
  Sum total_area;
  std::size_t receiving_faces = 0;

  // The same text nlohmann's dump(2) gives for the whole document, but written piece by piece:
  // the faces array can be huge and is never held as one document.
  auto member = [&out](const char* key, const std::string& value_text, bool last = false) {
    detail::write_member(out, key, value_text, last);
  };
  out << "{\n";
  member("libshadow_version", dump(Json(version())));
  member("scene", dump(Json(scene.source.string())));
  // The VTK files' points are relative to this (Scene::origin; models at projected coordinates).
  if (scene.origin) member("origin", dump(vec3(*scene.origin)));
  member("run", dump(run_json(scene, result, run), 2));
  member("lights", dump(lights_json(scene), 2));
  if (scene.sun) member("sun", dump(sun_json(scene), 2));

  // The faces' totals in face order, on one thread (the sums' bits follow their order)...
  std::vector<std::size_t> group_start;  // each face's first entry, then entries.size()
  for (std::size_t i = 0; i < entries.size();) {
    const std::size_t face_id = entries[i]->face_id;
    group_start.push_back(i);
    for (; i < entries.size() && entries[i]->face_id == face_id; ++i) {
      LightTotals& totals = per_light[entries[i]->light_id];
      totals.area.add(entries[i]->area);
      totals.lit_area.add(entries[i]->lit_area);
      totals.bound.add(entries[i]->lit_area_error_bound);
      if (face_id < scene.faces.size()) {
        LightTotals& m = per_mesh[{scene.faces[face_id].mesh, entries[i]->light_id}];
        m.area.add(entries[i]->area);
        m.lit_area.add(entries[i]->lit_area);
      }
    }
    total_area.add(entries[group_start.back()]->area);
  }
  receiving_faces = group_start.size();
  group_start.push_back(entries.size());
  // ... and their text on every thread.
  out << "  \"faces\": [";
  write_face_entries(out, scene, entries, group_start, fast, run != nullptr ? run->options.threads : 0);
  out << (receiving_faces == 0 ? "],\n" : "\n  ],\n");

  Json planes = Json::array();
  for (const PlaneShadow& shadow : result.plane_shadows) {
    const Plane& plane = scene.planes.at(shadow.plane_id);
    planes.push_back({{"name", plane.name},
                      {"plane", shadow.plane_id},
                      {"light", shadow.light_id},
                      {"light_name", detail::light_display_name(scene, shadow.light_id)},
                      {"shadow_area", shadow.area},
                      {"polygons", shadow.polygons.size()},
                      {"window_half_size", shadow.window_half_size},
                      {"reaches_window", shadow.reaches_window}});
  }
  member("planes", dump(planes, 2));

  Json per_light_json = Json::array();
  for (const auto& [light_id, totals] : per_light) {
    const double area = totals.area.value();
    const double lit = totals.lit_area.value();
    per_light_json.push_back({{"light", light_id},
                              {"light_name", detail::light_display_name(scene, light_id)},
                              {"area", area},
                              {"lit_area", lit},
                              {"lit_fraction", area > 0.0 ? lit / area : 0.0}});
    if (fast) per_light_json.back()["lit_area_error_bound"] = totals.bound.value() * (1 + 1e-12);
  }
  // Lit fractions per mesh and light: a building's or a city object's share of sun at a glance.
  Json per_mesh_json = Json::array();
  for (auto it = per_mesh.begin(); it != per_mesh.end();) {
    const std::size_t mesh = it->first.first;
    Json lights_of_mesh = Json::array();
    double mesh_area = 0.0;
    for (; it != per_mesh.end() && it->first.first == mesh; ++it) {
      const double area = it->second.area.value(), lit = it->second.lit_area.value();
      mesh_area = area;
      lights_of_mesh.push_back({{"light", it->first.second}, {"lit_area", lit}, {"lit_fraction", area > 0.0 ? lit / area : 0.0}});
    }
    per_mesh_json.push_back({{"mesh", mesh < scene.meshes.size() ? scene.meshes[mesh].name : std::string()},
                             {"area", mesh_area},
                             {"lights", std::move(lights_of_mesh)}});
  }
  Json summary = {{"faces", scene.faces.size()},
                        {"receiving_faces", receiving_faces},
                        {"lights", scene.lights.size()},
                        {"fragments", result.fragments.size()},
                        {"total_area", total_area.value()},
                        {"per_light", per_light_json},
                        {"per_mesh", per_mesh_json}};
  summary["arithmetic"] = fast ? "fast" : "exact";
  summary["skipped_faces"] = scene.skipped_faces.size();  // --skip-invalid (additive key)
  member("summary", dump(summary, 2));
  // The list only when faces were skipped: the reports of other runs keep their keys.
  if (!scene.skipped_faces.empty()) member("skipped_faces", dump(detail::skipped_faces_json(scene), 2));

  Json stats = {{"receivers", result.stats.receivers},
                      {"back_facing", result.stats.back_facing},
                      {"candidate_pairs", result.stats.candidate_pairs},
                      {"casting_pairs", result.stats.casting_pairs},
                      {"unshadowed", result.stats.unshadowed}};
  if (fast) {
    stats["fast_exact_fallbacks"] = result.stats.fast_exact_fallbacks;
    stats["fast_collapsed"] = result.stats.fast_collapsed;
  }
  if (result.stats.area_receivers > 0) {  // extended lights only (additive keys)
    stats["area_receivers"] = result.stats.area_receivers;
    stats["area_umbra_bounded"] = result.stats.area_umbra_bounded;
    stats["area_light_straddles"] = result.stats.area_light_straddles;
    stats["area_centre_behind"] = result.stats.area_centre_behind;
    stats["area_projection_pieces"] = result.stats.area_projection_pieces;
    stats["area_plane_pieces"] = result.stats.area_plane_pieces;
  }
  if (result.stats.dropped_cells > 0) stats["dropped_cells"] = result.stats.dropped_cells;  // additive key
  if (result.stats.tiled_receivers > 0) {  // receivers split into tiles only (additive keys)
    stats["tiled_receivers"] = result.stats.tiled_receivers;
    stats["tiles"] = result.stats.tiles;
  }
  member("stats", dump(stats, 2));

  Json warnings = Json::array();
  for (const Warning& w : scene.warnings) warnings.push_back(w.to_string());
  member("warnings", dump(warnings, 2), true);
  out << "}\n";
}

}  // namespace

}  // namespace shadow
