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
#include <cstdint>
#include <cstring>
#include <exception>
#include <map>
#include <memory>
#include <string>
#include <thread>
#include <utility>
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

/// A growing text buffer whose appends are inline copies. A million faces' entries appended
/// through std::string's out-of-line append (a capacity check and a copy call for every key)
/// spent a third of their instructions there.
class TextBuffer {
 public:
  void clear() noexcept { size_ = 0; }
  [[nodiscard]] const char* data() const noexcept { return data_.get(); }
  [[nodiscard]] std::size_t size() const noexcept { return size_; }
  /// Room for `n` more bytes: where they go. advance() to the end of what was written there.
  [[gnu::always_inline]] char* room(std::size_t n) {
    if (capacity_ - size_ < n) grow(n);
    return data_.get() + size_;
  }
  void advance(const char* end) noexcept { size_ = static_cast<std::size_t>(end - data_.get()); }
  [[gnu::always_inline]] void append(const char* text, std::size_t n) {
    if (n == 0) return;  // (no buffer yet: memcpy may not take a null pointer)
    std::memcpy(room(n), text, n);
    size_ += n;
  }
  void append(const std::string& text) { append(text.data(), text.size()); }
  /// A string literal (its length known at compile time: the copy is a few moves).
  template <std::size_t N>
  [[gnu::always_inline]] void literal(const char (&text)[N]) {
    append(text, N - 1);
  }

 private:
  [[gnu::noinline]] void grow(std::size_t n) {
    const std::size_t capacity = std::max({size_ + n, 2 * capacity_, std::size_t{4096}});
    std::unique_ptr<char[]> data(new char[capacity]);
    if (size_ > 0) std::memcpy(data.get(), data_.get(), size_);
    data_ = std::move(data);
    capacity_ = capacity;
  }
  std::unique_ptr<char[]> data_;
  std::size_t size_ = 0, capacity_ = 0;
};

/// A number as nlohmann's serializer writes it (its shortest round-trip form, `null` when not
/// finite), written at `at` (room for 64 bytes): the end of what was written.
char* write_number(char* at, double x) {
  if (!std::isfinite(x)) {
    std::memcpy(at, "null", 4);
    return at + 4;
  }
  // A whole number below 1e15 (a normal's 0 and 1, an axis-aligned face's azimuth and tilt, a
  // shadowed face's lit area): nlohmann writes its digits and ".0" (-0.0 too), written here
  // without its shortest-digits search, which took a sixth of a million faces' report.
  if (std::fabs(x) < 1e15 && x == std::trunc(x)) {
    if (std::signbit(x)) *at++ = '-';
    at = std::to_chars(at, at + 32, static_cast<long long>(std::fabs(x))).ptr;
    *at++ = '.';
    *at++ = '0';
    return at;
  }
  return nlohmann::detail::to_chars(at, at + 64, x);
}

void append_number(TextBuffer& out, double x) { out.advance(write_number(out.room(64), x)); }

void append_unsigned(TextBuffer& out, std::size_t n) {
  char* at = out.room(24);
  out.advance(std::to_chars(at, at + 24, n).ptr);
}

/// Whether nlohmann writes `text` as it is between quotes: printable ASCII without a quote or a
/// backslash.
bool plain_json_text(const std::string& text) {
  return std::all_of(text.begin(), text.end(), [](char c) { return c >= 0x20 && c < 0x7f && c != '"' && c != '\\'; });
}

/// A JSON string as nlohmann writes it (escapes, bytes that are not UTF-8 replaced): plain text
/// (plain_json_text) is copied as is, anything else goes through nlohmann.
std::string json_string(const std::string& text) {
  if (plain_json_text(text)) return '"' + text + '"';
  return Json(text).dump(-1, ' ', false, Json::error_handler_t::replace);
}

void append_string(TextBuffer& out, const std::string& text) {
  if (plain_json_text(text)) {
    char* at = out.room(text.size() + 2);
    *at++ = '"';
    std::memcpy(at, text.data(), text.size());
    at += text.size();
    *at++ = '"';
    out.advance(at);
  } else {
    out.append(json_string(text));
  }
}

/// A face's source as append_string(out, source.to_string()) writes it, without making that
/// string when both parts are plain (a million faces: a string each). `plain_file`: the last file
/// name found plain, which most faces share (one mesh file's faces follow one another).
void append_source(TextBuffer& out, const SourceLocation& source, std::string& plain_file) {
  if (source.file.empty() || source.place.empty()) {
    append_string(out, source.to_string());
    return;
  }
  if (source.file != plain_file) {
    if (!plain_json_text(source.file)) {
      append_string(out, source.to_string());
      return;
    }
    plain_file = source.file;
  }
  if (!plain_json_text(source.place)) {
    append_string(out, source.to_string());
    return;
  }
  char* at = out.room(source.file.size() + source.place.size() + 4);
  *at++ = '"';
  std::memcpy(at, source.file.data(), source.file.size());
  at += source.file.size();
  *at++ = ':';
  *at++ = ' ';
  std::memcpy(at, source.place.data(), source.place.size());
  at += source.place.size();
  *at++ = '"';
  out.advance(at);
}

/// What face entries share: each light's and mesh's name as JSON text, made once.
struct EntryNames {
  std::vector<std::string> lights;  ///< by light id; ids past the scene's are made when met
  std::vector<std::string> meshes;  ///< by mesh id
  EntryNames(const Scene& scene, std::size_t light_ids) {
    for (std::size_t l = 0; l < light_ids; ++l) {
      lights.push_back(json_string(detail::light_display_name(scene, l)));
    }
    for (const Mesh& mesh : scene.meshes) {
      meshes.push_back(json_string(mesh.name));
    }
  }
};

/// Appends face `face_id`'s report entry from its `count` FaceLighting entries (all for `face_id`), as
/// the faces array holds it (4 spaces in, 2 more a level): the text nlohmann's dump(2) gives for
/// the whole document, written directly (a million faces' entries built as values and dumped
/// took most of a report's time). Keys in this order; those after `faces_light` are additive.
void append_face_entry(TextBuffer& out, const Scene& scene, const EntryNames& names, std::size_t face_id,
                       const FaceLighting* const* entries, std::size_t count, bool fast, std::string& plain_file) {
  out.literal("{\n      \"id\": ");
  append_unsigned(out, face_id);
  out.literal(",\n      \"mesh\": ");
  const std::size_t mesh = face_id < scene.faces.size() ? scene.faces[face_id].mesh : scene.meshes.size();
  if (mesh < names.meshes.size()) out.append(names.meshes[mesh]);
  else out.literal("\"\"");
  if (face_id < scene.faces.size()) {
    const Face& face = scene.faces[face_id];
    const detail::FaceOrientation o = detail::face_orientation(face, detail::north_axis_of(scene));
    out.literal(",\n      \"name\": ");
    append_string(out, face.name);
    out.literal(",\n      \"source\": ");
    append_source(out, face.source, plain_file);
    if (!face.kind.empty()) {
      out.literal(",\n      \"kind\": ");
      append_string(out, face.kind);
    }
    out.literal(",\n      \"normal\": [\n        ");
    append_number(out, o.normal.x);
    out.literal(",\n        ");
    append_number(out, o.normal.y);
    out.literal(",\n        ");
    append_number(out, o.normal.z);
    out.literal("\n      ],\n      \"azimuth\": ");
    append_number(out, o.azimuth);
    out.literal(",\n      \"tilt\": ");
    append_number(out, o.tilt);
  }
  out.literal(",\n      \"area\": ");
  append_number(out, entries[0]->area);
  out.literal(",\n      \"lights\": [");
  for (std::size_t i = 0; i < count; ++i) {
    const FaceLighting& e = *entries[i];
    if (i == 0) out.literal("\n        {\n          \"light\": ");
    else out.literal(",\n        {\n          \"light\": ");
    append_unsigned(out, e.light_id);
    out.literal(",\n          \"light_name\": ");
    if (e.light_id < names.lights.size()) out.append(names.lights[e.light_id]);
    else append_string(out, detail::light_display_name(scene, e.light_id));
    out.literal(",\n          \"lit_area\": ");
    append_number(out, e.lit_area);
    out.literal(",\n          \"shadow_area\": ");
    append_number(out, e.shadow_area);
    out.literal(",\n          \"lit_fraction\": ");
    append_number(out, e.lit_fraction);
    if (e.faces_light) out.literal(",\n          \"faces_light\": true");
    else out.literal(",\n          \"faces_light\": false");
    // The fast path's certificate: |lit_area - exact lit area| <= this.
    if (fast) {
      out.literal(",\n          \"lit_area_error_bound\": ");
      append_number(out, e.lit_area_error_bound);
    }
    // Cells too thin to be written as double polygons (only when there are some).
    if (e.dropped_area > 0) {
      out.literal(",\n          \"dropped_area\": ");
      append_number(out, e.dropped_area);
    }
    // An extended light's exact regions (docs/area-lights.md).
    if (e.light_id < scene.lights.size() && scene.lights[e.light_id].is_extended()) {
      out.literal(",\n          \"fully_lit_area\": ");
      append_number(out, e.fully_lit_area);
      out.literal(",\n          \"penumbra_area\": ");
      append_number(out, e.penumbra_area);
      out.literal(",\n          \"umbra_area\": ");
      append_number(out, e.umbra_area);
    }
    out.literal("\n        }");
  }
  out.literal("\n      ]\n    }");
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
  std::vector<TextBuffer> made(window), written(window);
  auto make = [&](std::size_t first, std::size_t count) {
    runtime::parallel_for(count, static_cast<unsigned>(std::min<std::size_t>(threads, count)), [&](unsigned, std::size_t k) {
      TextBuffer& text = made[k];
      text.clear();
      std::string plain_file;
      const std::size_t end = std::min(receiving_faces, (first + k + 1) * kFacesPerBlock);
      for (std::size_t g = (first + k) * kFacesPerBlock; g < end; ++g) {
        const FaceLighting* const* group = entries.data() + group_start[g];
        if (g == 0) text.literal("\n    ");
        else text.literal(",\n    ");
        append_face_entry(text, scene, names, group[0]->face_id, group, group_start[g + 1] - group_start[g], fast,
                          plain_file);
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
        for (std::size_t k = 0; k < count; ++k)
          out.write(written[k].data(), static_cast<std::streamsize>(written[k].size()));
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

/// The summary's totals, each face's entries after the other's in face order (the sums' bits
/// follow their order), and where each face's entries start.
struct ReportTotals {
  struct LightTotals {
    Sum area;
    Sum lit_area;
    Sum bound;
  };
  std::map<std::size_t, LightTotals> per_light;
  std::map<std::pair<std::size_t, std::size_t>, LightTotals> per_mesh;  // (mesh, light)
  Sum total_area;
  std::vector<std::size_t> group_start;  ///< each face's first entry, then entries.size()

  /// `entries` by face, then light. The totals last added to are kept at hand: neighbouring
  /// entries mostly share their light and mesh, and a map's search for each of a million
  /// entries was most of this loop.
  ReportTotals(const Scene& scene, const std::vector<const FaceLighting*>& entries) {
    std::pair<std::size_t, LightTotals*> last_light{SIZE_MAX, nullptr};
    std::pair<std::pair<std::size_t, std::size_t>, LightTotals*> last_mesh{{SIZE_MAX, SIZE_MAX}, nullptr};
    for (std::size_t i = 0; i < entries.size();) {
      const std::size_t face_id = entries[i]->face_id;
      group_start.push_back(i);
      for (; i < entries.size() && entries[i]->face_id == face_id; ++i) {
        const std::size_t light_id = entries[i]->light_id;
        if (last_light.second == nullptr || last_light.first != light_id) last_light = {light_id, &per_light[light_id]};
        LightTotals& totals = *last_light.second;
        totals.area.add(entries[i]->area);
        totals.lit_area.add(entries[i]->lit_area);
        totals.bound.add(entries[i]->lit_area_error_bound);
        if (face_id < scene.faces.size()) {
          const std::pair<std::size_t, std::size_t> key{scene.faces[face_id].mesh, light_id};
          if (last_mesh.second == nullptr || last_mesh.first != key) last_mesh = {key, &per_mesh[key]};
          LightTotals& m = *last_mesh.second;
          m.area.add(entries[i]->area);
          m.lit_area.add(entries[i]->lit_area);
        }
      }
      total_area.add(entries[group_start.back()]->area);
    }
    group_start.push_back(entries.size());
  }
};

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

  const bool fast = result.arithmetic == Arithmetic::Fast;

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
  const ReportTotals report_totals(scene, entries);
  const auto& [per_light, per_mesh, total_area, group_start] = report_totals;
  const std::size_t receiving_faces = group_start.size() - 1;
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
