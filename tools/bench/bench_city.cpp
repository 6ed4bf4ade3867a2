// SPDX-License-Identifier: GPL-3.0-or-later
// shadow-bench's city benchmarks (bench_city.hpp): each row in a forked child where peak memory
// or a clean process matters, printed as Markdown tables.
#include "bench_city.hpp"

#include <shadow/shadow.hpp>
#include <shadow/sun.hpp>

#include <CLI/CLI.hpp>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <cstring>
#include <ctime>
#include <fstream>
#include <functional>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace bench {

int run_comb(std::size_t teeth, bool polygons) {
  const std::vector<glm::dvec3> comb = shadow::comb_polygon(teeth, 1);
  const double n = static_cast<double>(teeth);
  shadow::Scene scene;
  shadow::add_mesh(scene, "ground", {{{-5, -5, 0}, {n + 5, -5, 0}, {n + 5, 15, 0}, {-5, 15, 0}}});
  shadow::add_mesh(scene, "comb", {comb});
  scene.lights.push_back(shadow::directional_light("sun", {0.1, 0.2, 1}));
  const auto t0 = std::chrono::steady_clock::now();
  shadow::validate_scene(scene);
  shadow::ShadowOptions options;
  options.threads = 1;
  options.polygons = polygons;
  const shadow::ShadowResult result = shadow::compute_shadows(scene, options);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const shadow::FaceLighting* ground = result.find(0, 0);
  std::printf("comb of %zu vertices over a ground, %s: %.3f s, ground shadow %.17g m^2 (exact: %.17g)\n", comb.size(),
              polygons ? "polygons" : "areas only", seconds, ground ? ground->shadow_area : -1.0, 5.5 * n);
  return ground && ground->shadow_area == 5.5 * n ? 0 : 1;
}

int run_comb_lamp(std::size_t teeth, bool polygons, unsigned threads, double lamp_height) {
  std::vector<glm::dvec3> comb = shadow::comb_polygon(teeth, 1);
  const double n = static_cast<double>(teeth);
  for (glm::dvec3& v : comb) {
    v.x = 2 + v.x * (16 / n);
    v.y = 2 + v.y * 1.6;
  }
  shadow::Scene scene;
  shadow::add_mesh(scene, "ground", {shadow::rectangle_z(0, 0, 20, 20, 0)});
  shadow::add_mesh(scene, "comb", {comb});
  scene.lights.push_back(shadow::directional_light("sun", {0.1, 0.2, 1}));
  scene.lights.push_back(shadow::point_light("lamp", {10.25, 9.75, lamp_height}));
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  shadow::validate_scene(scene);
  shadow::ShadowOptions options;
  options.threads = threads;
  options.polygons = polygons;
  options.planes = false;
  const shadow::ShadowResult result = shadow::compute_shadows(scene, options);
  const double total = std::chrono::duration<double>(Clock::now() - t0).count();
  double alone[2];
  for (std::size_t l = 0; l < 2; ++l) {
    const auto t1 = Clock::now();
    const shadow::ShadowEngine engine(scene, threads);
    const shadow::ShadowResult one = engine.compute(scene.lights[l], l, options);
    alone[l] = std::chrono::duration<double>(Clock::now() - t1).count();
    const shadow::FaceLighting* a = one.find(0, l);
    const shadow::FaceLighting* b = result.find(0, l);
    if (!a || !b || a->lit_area != b->lit_area) return 1;
  }
  const double area = 5.5 * 16 * 1.6;  // the comb's: 5.5 n in its own units, scaled by 16 / n and 1.6
  const double k = lamp_height / (lamp_height - 1);
  const bool on_ground = 10.25 - 8.25 * k >= 0 && 10.25 + 7.75 * k <= 20 && 9.75 - 7.75 * k >= 0 && 9.75 + 8.25 * k <= 20;
  const shadow::FaceLighting* sun = result.find(0, 0);
  const shadow::FaceLighting* lamp = result.find(0, 1);
  std::printf("comb of %zu vertices over a 20 x 20 m ground, sun and lamp at height %g, %s, %u threads: %.3f s "
              "(sun alone %.3f s, lamp alone %.3f s); ground shadow %.17g (sun, %.17g expected), %.17g (lamp%s)\n",
              comb.size(), lamp_height, polygons ? "polygons" : "areas only", threads, total, alone[0], alone[1],
              sun ? sun->shadow_area : -1.0, area, lamp ? lamp->shadow_area : -1.0,
              on_ground ? "" : ", partly off the ground");
  if (!sun || std::abs(sun->shadow_area - area) > 1e-9 * area) return 1;
  if (lamp && on_ground && std::abs(lamp->shadow_area - k * k * area) > 1e-9 * area)
    return 1;
  return lamp ? 0 : 1;
}

int run_series_bench(std::size_t boxes, std::size_t sample, bool baseline, unsigned threads,
                     double latitude, const std::string& arithmetic, bool ground, const std::string& sun_path,
                     std::size_t runs) {
  using Clock = std::chrono::steady_clock;
  const double pi = 3.14159265358979323846;
  const double phi = latitude * pi / 180.0;
  std::vector<shadow::Light> year;
  if (sun_path == "spa") {
    shadow::SunPeriod period;
    period.site.latitude = latitude;
    period.site.longitude = 2.35;
    period.utc_offset_hours = 1.0;
    period.start = "2026-01-01";
    period.end = "2026-12-31";
    period.step_minutes = 60;
    for (const shadow::SunInstant& instant : shadow::expand_sun_period(period))
      if (instant.position.elevation > 0) year.push_back(shadow::directional_light("sun", instant.position.to_light));
  }
  for (int day = 1; day <= 365 && sun_path != "spa"; ++day) {
    const double decl = 23.44 * pi / 180.0 * std::sin(2.0 * pi * (284.0 + day) / 365.0);
    for (int hour = 0; hour < 24; ++hour) {
      const double h = (hour - 12.0) * 15.0 * pi / 180.0;
      const glm::dvec3 d{-std::cos(decl) * std::sin(h),
                         std::sin(decl) * std::cos(phi) - std::cos(decl) * std::cos(h) * std::sin(phi),
                         std::sin(decl) * std::sin(phi) + std::cos(decl) * std::cos(h) * std::cos(phi)};
      if (d.z > 0) year.push_back(shadow::directional_light("sun", d));
    }
  }
  sample = std::min(sample, year.size());
  // `runs` runs of consecutive hourly suns spread evenly over the year (the same hour on
  // neighbouring days: what a whole year's series has), or every instant alone.
  runs = runs == 0 ? sample : std::min(runs, sample);
  std::vector<shadow::Light> lights;
  for (std::size_t r = 0; r < runs; ++r) {
    const std::size_t length = (r + 1) * sample / runs - r * sample / runs;
    for (std::size_t i = 0; i < length; ++i) lights.push_back(year[(r * year.size() / runs + i) % year.size()]);
  }
  const double extent = 500.0 * std::sqrt(static_cast<double>(boxes) / 1000.0);
  shadow::Scene scene = shadow::make_city(boxes, extent, 2026);
  scene.meshes[0].receiver = ground;  // mesh 0 is the ground (one face)
  shadow::validate_scene(scene);
  const auto t0 = Clock::now();
  const shadow::ShadowEngine engine(scene, threads);
  const double prepare = std::chrono::duration<double>(Clock::now() - t0).count();
  std::printf("city of %zu boxes (%zu faces%s), latitude %.1f, sun path %s: %zu hourly suns above the horizon in a year; "
              "sample of %zu in %zu run%s, %u threads, preparation %.3f s\n",
              boxes, scene.faces.size(), ground ? "" : ", ground not receiving", latitude, sun_path.c_str(), year.size(),
              sample, runs, runs == 1 ? "" : "s", threads, prepare);
  // CPU time too: on a shared machine the wall clock measures the other processes as much as
  // this one; CPU seconds / threads is what an otherwise idle machine would take.
  const auto cpu_now = [] {
    timespec ts{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
  };
  std::printf("| arithmetic | method | instants | wall (s) | wall per instant (ms) | CPU per instant (ms) | year: wall (s) | year: CPU / threads (s) | fallbacks | lit fraction |\n");
  std::printf("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  int status = 0;
  for (const std::string a : {"exact", "fast"}) {
    if (arithmetic != "both" && arithmetic != a) continue;
    {
      // Warm-up, not timed: the first computation of a process pays for page faults and the
      // allocator's growth, which would count against whichever method ran first.
      shadow::ShadowOptions warm;
      warm.threads = threads;
      warm.polygons = false;
      warm.arithmetic = a == "fast" ? shadow::Arithmetic::Fast : shadow::Arithmetic::Exact;
      (void)engine.compute(lights[sample / 2], 0, warm);
    }
    shadow::SeriesOptions options;
    options.threads = threads;
    options.arithmetic = a == "fast" ? shadow::Arithmetic::Fast : shadow::Arithmetic::Exact;
    const auto s0 = Clock::now();
    const double c0 = cpu_now();
    const shadow::SeriesResult series = engine.compute_series(lights, options);
    const double cpu = cpu_now() - c0;
    const double seconds = std::chrono::duration<double>(Clock::now() - s0).count();
    double lit = 0, area = 0;
    for (std::size_t r = 0; r < series.faces.size(); ++r)
      for (std::size_t i = 0; i < series.instants; ++i) {
        lit += series.lit_area[series.at(r, i)];
        area += series.area[r];
      }
    const double per = seconds / static_cast<double>(sample);
    const double cpu_per = cpu / static_cast<double>(sample);
    std::printf("| %s | compute_series | %zu | %.3f | %.1f | %.1f | %.0f | %.0f | %llu | %.6f |\n", a.c_str(), sample,
                seconds, 1000 * per, 1000 * cpu_per, per * static_cast<double>(year.size()) + prepare,
                cpu_per * static_cast<double>(year.size()) / threads + prepare,
                static_cast<unsigned long long>(series.stats.fast_exact_fallbacks), area > 0 ? lit / area : 0.0);
    // What neighbouring suns could share: the receivers each kind of work went to, per instant
    // (back-facing and unshadowed ones need no union; only the shadowed ones do).
    const shadow::ShadowStats& st = series.stats;
    const double per_instant = 1.0 / static_cast<double>(sample);
    std::fprintf(stderr,
                 "%s per instant: %.0f receivers, %.0f back-facing, %.0f unshadowed, %.0f shadowed, %.0f candidate "
                 "pairs, %.0f casting pairs\n",
                 a.c_str(), static_cast<double>(st.receivers) * per_instant,
                 static_cast<double>(st.back_facing) * per_instant, static_cast<double>(st.unshadowed) * per_instant,
                 static_cast<double>(st.receivers - st.back_facing - st.unshadowed) * per_instant,
                 static_cast<double>(st.candidate_pairs) * per_instant,
                 static_cast<double>(st.casting_pairs) * per_instant);
    std::fflush(stdout);
    const std::size_t n = sample;
    if (!baseline) continue;
    // The same instants one call each (what a loop over compute(light) costs), and the check
    // that the values agree bit for bit.
    shadow::ShadowOptions one;
    one.threads = threads;
    one.polygons = false;
    one.arithmetic = options.arithmetic;
    const auto b0 = Clock::now();
    const double bc0 = cpu_now();
    std::size_t differ = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const shadow::ShadowResult result = engine.compute(lights[i], i, one);
      for (std::size_t r = 0; r < result.lighting.size(); ++r)
        differ += result.lighting[r].lit_area != series.lit_area[series.at(r, i)] ? 1 : 0;
    }
    const double bcpu = (cpu_now() - bc0) / static_cast<double>(n);
    const double bseconds = std::chrono::duration<double>(Clock::now() - b0).count();
    const double bper = bseconds / static_cast<double>(n);
    std::printf("| %s | compute(light) each | %zu | %.3f | %.1f | %.1f | %.0f | %.0f | | %s |\n", a.c_str(), n, bseconds,
                1000 * bper, 1000 * bcpu, bper * static_cast<double>(year.size()) + prepare,
                bcpu * static_cast<double>(year.size()) / threads + prepare, differ == 0 ? "same values" : "DIFFERENT");
    std::fflush(stdout);
    if (differ != 0) status = 1;
  }
  return status;
}

namespace {



/// One timing of compute_plane_shadows, measured in a child process (bench_planes below).
struct PlaneTiming {
  double wall_s = 0, cpu_s = 0, area = 0;
  long peak_kib = 0;
  std::size_t polygons = 0, regions = 0;
  bool reaches = false, ok = false;
};

double cpu_seconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

/// Runs `child` in a forked process (so that each measurement has its own peak memory and no
/// warm caches) and returns the text it produced; false when the child failed or could not start.
bool output_of_child(const std::function<std::string()>& child, std::string& text) {
  int fds[2];
  if (pipe(fds) != 0) return false;
  const pid_t pid = fork();
  if (pid == 0) {
    close(fds[0]);
    const std::string out = child();
    if (out.empty() || write(fds[1], out.data(), out.size()) < 0) _exit(1);
    _exit(0);
  }
  close(fds[1]);
  text.clear();
  char buffer[512];
  ssize_t got;
  while ((got = read(fds[0], buffer, sizeof buffer)) > 0) text.append(buffer, static_cast<std::size_t>(got));
  close(fds[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  return pid > 0 && WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

/// The benchmark city of `boxes` boxes at constant density under one sun from the south-east.
shadow::Scene city_under_sun(std::size_t boxes, double elevation) {
  const double extent = 500.0 * std::sqrt(static_cast<double>(boxes) / 1000.0);
  shadow::Scene scene = shadow::make_city(boxes, extent, 2026);
  scene.lights.push_back(shadow::directional_light("sun", shadow::sun_direction(elevation, 135.0)));
  return scene;
}

/// Plane shadows of the city on its ground plane, in a forked child: wall and CPU time of the
/// fastest of `repeat` runs (CPU time of that run, all threads).
PlaneTiming time_planes(std::size_t boxes, double elevation, unsigned threads, int repeat) {
  std::string text;
  const bool ran = output_of_child([&]() -> std::string {
    shadow::Scene scene = city_under_sun(boxes, elevation);
    scene.planes.push_back({"ground", {0, 0, 0}, {0, 0, 1}});
    shadow::validate_scene(scene);
    shadow::ShadowOptions options;
    options.threads = threads;
    PlaneTiming t;
    t.wall_s = 1e300;
    for (int r = 0; r < repeat; ++r) {
      const double cpu0 = cpu_seconds();
      const auto t0 = std::chrono::steady_clock::now();
      const std::vector<shadow::PlaneShadow> shadows = shadow::compute_plane_shadows(scene, options);
      const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      const double cpu = cpu_seconds() - cpu0;
      if (wall < t.wall_s) {
        t.wall_s = wall;
        t.cpu_s = cpu;
      }
      const shadow::PlaneShadow& s = shadows.at(0);
      t.area = s.area;
      t.polygons = s.polygons.size();
      t.regions = s.region_id.empty() ? 0 : *std::max_element(s.region_id.begin(), s.region_id.end()) + 1;
      t.reaches = s.reaches_window;
    }
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    char line[256];
    const int n = std::snprintf(line, sizeof line, "%.17g %.17g %a %ld %zu %zu %d", t.wall_s, t.cpu_s, t.area,
                                usage.ru_maxrss, t.polygons, t.regions, t.reaches ? 1 : 0);
    return n > 0 ? std::string(line, static_cast<std::size_t>(n)) : std::string();
  }, text);
  PlaneTiming t;
  int reaches = 0;
  t.ok = ran && std::sscanf(text.c_str(), "%lg %lg %la %ld %zu %zu %d", &t.wall_s, &t.cpu_s, &t.area, &t.peak_kib, &t.polygons,
                     &t.regions, &reaches) == 7;
  t.reaches = reaches != 0;
  return t;
}

}  // namespace

int run_planes_bench(const std::vector<std::size_t>& sizes, const std::vector<double>& elevations,
                     const std::vector<unsigned>& threads, int repeat, const std::string& label) {
  std::printf("| build | boxes | sun | threads | wall (s) | CPU (s) | peak (MiB) | polygons | regions | area (m^2) |\n");
  std::printf("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (std::size_t boxes : sizes)
    for (double elevation : elevations)
      for (unsigned t : threads) {
        const PlaneTiming m = time_planes(boxes, elevation, t, repeat);
        if (!m.ok) {
          std::printf("| %s | %zu | %.0f | %u | failed |\n", label.c_str(), boxes, elevation, t);
          continue;
        }
        std::printf("| %s | %zu | %.0f° | %u | %.3f | %.3f | %.0f | %zu | %zu | %.6f (%a) |\n", label.c_str(), boxes,
                    elevation, t, m.wall_s, m.cpu_s, m.peak_kib / 1024.0, m.polygons, m.regions, m.area, m.area);
        std::fflush(stdout);
      }
  return 0;
}

namespace {


/// One sun on the city, in a forked child (bench_city_sun below): wall and CPU time of the
/// computation (areas only), the process's peak memory, the sum of the lit areas.
struct SunTiming {
  double setup_s = 0, wall_s = 0, cpu_s = 0, lit = 0, bound = 0;
  long peak_kib = 0;
  unsigned long long fallbacks = 0;
  bool ok = false;
};

SunTiming time_city_sun(std::size_t boxes, double elevation, const std::string& arithmetic, unsigned threads) {
  std::string text;
  const bool ran = output_of_child([&]() -> std::string {
    shadow::Scene scene = city_under_sun(boxes, elevation);
    shadow::validate_scene(scene);
    SunTiming t;
    const auto s0 = std::chrono::steady_clock::now();
    const shadow::ShadowEngine engine(scene, threads);
    t.setup_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - s0).count();
    shadow::ShadowOptions options;
    options.threads = threads;
    options.polygons = false;
    options.planes = false;
    options.arithmetic = arithmetic == "fast" ? shadow::Arithmetic::Fast : shadow::Arithmetic::Exact;
    const double cpu0 = cpu_seconds();
    const auto t0 = std::chrono::steady_clock::now();
    const shadow::ShadowResult result = engine.compute(options);
    t.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    t.cpu_s = cpu_seconds() - cpu0;
    for (const shadow::FaceLighting& f : result.lighting) {
      t.lit += f.lit_area;
      t.bound += f.lit_area_error_bound;
    }
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    char line[256];
    const int n = std::snprintf(line, sizeof line, "%.17g %.17g %.17g %a %a %ld %llu", t.setup_s, t.wall_s, t.cpu_s, t.lit,
                                t.bound, usage.ru_maxrss,
                                static_cast<unsigned long long>(result.stats.fast_exact_fallbacks));
    return n > 0 ? std::string(line, static_cast<std::size_t>(n)) : std::string();
  }, text);
  SunTiming t;
  t.ok = ran && std::sscanf(text.c_str(), "%lg %lg %lg %la %la %ld %llu", &t.setup_s, &t.wall_s, &t.cpu_s, &t.lit, &t.bound,
                     &t.peak_kib, &t.fallbacks) == 7;
  return t;
}

/// The city's ground (face 0, the square [-10, extent + 10]^2 at z = 0) made into another shape
/// of about its size (docs/tiles.md, receivers that are not rectangles): "rectangle" leaves it,
/// "octagon" cuts the square's corners (a regular octagon in it), "rotated" turns the square by
/// 30 degrees about its centre. Throws on another name.
void reshape_ground(shadow::Scene& scene, const std::string& shape) {
  if (shape == "rectangle") return;
  std::vector<glm::dvec3>& ground = scene.faces.at(0).vertices;
  double lo = ground[0].x, hi = ground[0].x;
  for (const glm::dvec3& v : ground) {
    lo = std::min({lo, v.x, v.y});
    hi = std::max({hi, v.x, v.y});
  }
  const double side = hi - lo, mid = lo + side / 2;
  std::vector<glm::dvec3> outline;
  if (shape == "octagon") {
    const double cut = side / (2 + std::sqrt(2.0));
    outline = {{lo + cut, lo, 0}, {hi - cut, lo, 0}, {hi, lo + cut, 0}, {hi, hi - cut, 0},
               {hi - cut, hi, 0}, {lo + cut, hi, 0}, {lo, hi - cut, 0}, {lo, lo + cut, 0}};
  } else if (shape == "rotated") {
    const double a = 30 * M_PI / 180, c = std::cos(a), s = std::sin(a), h = side / 2;
    for (const glm::dvec2 d : {glm::dvec2(-h, -h), glm::dvec2(h, -h), glm::dvec2(h, h), glm::dvec2(-h, h)})
      outline.emplace_back(mid + c * d.x - s * d.y, mid + s * d.x + c * d.y, 0);
  } else {
    throw std::invalid_argument("unknown ground shape '" + shape + "' (rectangle, octagon, rotated)");
  }
  ground = outline;
}

/// One sun on the city with given tile thresholds, in a forked child (bench_tiles below).
struct TileTiming {
  double wall_s = 0, cpu_s = 0, item_s = 0, longest_s = 0, lit = 0, bound = 0;
  long peak_kib = 0;
  unsigned long long tiles = 0, tiled = 0, digest = 0;
  bool ok = false;
};

TileTiming time_tiles(std::size_t boxes, double elevation, bool fast, unsigned threads, std::size_t tile_casters,
                      std::size_t fast_tile_casters, const std::string& ground) {
  std::string text;
  const bool ran = output_of_child([&]() -> std::string {
    shadow::Scene scene = city_under_sun(boxes, elevation);
    reshape_ground(scene, ground);
    shadow::validate_scene(scene);
    const shadow::ShadowEngine engine(scene, threads);
    shadow::ShadowOptions options;
    options.threads = threads;
    options.polygons = false;
    options.planes = false;
    options.arithmetic = fast ? shadow::Arithmetic::Fast : shadow::Arithmetic::Exact;
    options.tile_casters = tile_casters;
    options.fast_tile_casters = fast_tile_casters;
    const double cpu0 = cpu_seconds();
    const auto t0 = std::chrono::steady_clock::now();
    const shadow::ShadowResult result = engine.compute(options);
    TileTiming t;
    t.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    t.cpu_s = cpu_seconds() - cpu0;
    std::uint64_t h = 1469598103934665603ull;  // FNV-1a over every lit area's bits
    for (const shadow::FaceLighting& f : result.lighting) {
      t.lit += f.lit_area;
      t.bound += f.lit_area_error_bound;
      std::uint64_t bits = 0;
      std::memcpy(&bits, &f.lit_area, sizeof bits);
      for (int b = 0; b < 8; ++b) h = (h ^ ((bits >> (8 * b)) & 0xff)) * 1099511628211ull;
    }
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    char line[512];
    const int n = std::snprintf(line, sizeof line, "%.17g %.17g %.17g %.17g %a %a %ld %llu %llu %llu", t.wall_s, t.cpu_s,
                                result.stats.item_seconds, result.stats.longest_item_seconds, t.lit, t.bound,
                                usage.ru_maxrss, static_cast<unsigned long long>(result.stats.tiles),
                                static_cast<unsigned long long>(result.stats.tiled_receivers),
                                static_cast<unsigned long long>(h));
    return n > 0 ? std::string(line, static_cast<std::size_t>(n)) : std::string();
  }, text);
  TileTiming t;
  t.ok = ran && std::sscanf(text.c_str(), "%lg %lg %lg %lg %la %la %ld %llu %llu %llu", &t.wall_s, &t.cpu_s, &t.item_s,
                     &t.longest_s, &t.lit, &t.bound, &t.peak_kib, &t.tiles, &t.tiled, &t.digest) == 10;
  return t;
}

}  // namespace

int run_tiles_bench(const std::vector<std::size_t>& sizes, const std::vector<double>& elevations,
                    const std::vector<std::string>& arithmetics, const std::vector<unsigned>& threads,
                    std::size_t tile_casters, std::size_t fast_tile_casters, bool untiled,
                    const std::vector<std::string>& grounds) {
  std::printf("| ground | boxes | sun | arithmetic | tiles | threads | wall (s) | CPU (s) | items' CPU (s) | longest item (s) | longest / items | peak (MiB) | tiles made | lit area (m^2) | same bits as untiled |\n");
  std::printf("|---|---:|---:|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|\n");
  for (const std::string& ground : grounds)
  for (std::size_t boxes : sizes)
    for (double elevation : elevations)
      for (const std::string& a : arithmetics) {
        const bool fast = a == "fast";
        unsigned long long reference = 0;
        bool have_reference = false;
        double cpu_one = 0;
        for (int tiled = untiled ? 0 : 1; tiled <= 1; ++tiled)
          for (unsigned t : threads) {
            const TileTiming m =
                time_tiles(boxes, elevation, fast, t, tiled ? tile_casters : 0, tiled ? fast_tile_casters : 0, ground);
            if (!m.ok) {
              std::printf("| %s | %zu | %.0f° | %s | %s | %u | failed |\n", ground.c_str(), boxes, elevation, a.c_str(),
                          tiled ? "on" : "off", t);
              continue;
            }
            if (!have_reference) {
              reference = m.digest;
              have_reference = true;
            }
            if (t == 1) cpu_one = m.cpu_s;
            char speed[64] = "";
            // On a shared machine the wall clock measures the other processes too: the 2-thread
            // time an idle machine would take is the serial part (CPU outside the items) plus
            // half the items' CPU, plus up to the longest item for the last one to finish.
            if (t == 2 && cpu_one > 0) {
              const double serial = std::max(0.0, m.cpu_s - m.item_s);
              std::snprintf(speed, sizeof speed, " (CPU-based 1->2: %.2f-%.2f)",
                            cpu_one / (serial + m.item_s / 2 + m.longest_s), cpu_one / (serial + m.item_s / 2));
            }
            std::printf("| %s | %zu | %.0f° | %s | %s | %u | %.3f | %.3f%s | %.3f | %.3f | %.2f%% | %.0f | %llu | %.6f | %s |\n",
                        ground.c_str(), boxes, elevation, a.c_str(), tiled ? "on" : "off", t, m.wall_s, m.cpu_s, speed, m.item_s, m.longest_s,
                        m.item_s > 0 ? 100 * m.longest_s / m.item_s : 0.0, m.peak_kib / 1024.0, m.tiles, m.lit,
                        m.digest == reference ? "yes" : (fast ? "no (fast: within bounds)" : "NO"));
            std::fflush(stdout);
          }
      }
  return 0;
}

int run_low_sun_bench(const std::vector<std::size_t>& sizes, const std::vector<double>& elevations,
                      const std::vector<std::string>& arithmetics, const std::vector<unsigned>& threads,
                      const std::string& label) {
  std::printf("| build | boxes | sun | arithmetic | threads | engine setup (s) | wall (s) | CPU (s) | peak (MiB) | fallbacks | lit area (m^2) | sum of bounds (m^2) |\n");
  std::printf("|---|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (std::size_t boxes : sizes)
    for (double elevation : elevations)
      for (unsigned t : threads)
        for (const std::string& a : arithmetics) {
          const SunTiming m = time_city_sun(boxes, elevation, a, t);
          if (!m.ok) {
            std::printf("| %s | %zu | %.0f° | %s | %u | failed |\n", label.c_str(), boxes, elevation, a.c_str(), t);
            continue;
          }
          std::printf("| %s | %zu | %.0f° | %s | %u | %.3f | %.3f | %.3f | %.0f | %llu | %.6f | %.3g |\n", label.c_str(), boxes,
                      elevation, a.c_str(), t, m.setup_s, m.wall_s, m.cpu_s, m.peak_kib / 1024.0, m.fallbacks, m.lit, m.bound);
          std::fflush(stdout);
        }
  return 0;
}

CLI::App* add_series_command(CLI::App& app, SeriesArgs& a) {
  CLI::App* cmd = app.add_subcommand(
      "series", "A year of hourly suns on a city, areas only: a sample of instants, extrapolated to the year");
  cmd->add_option("--boxes", a.boxes, "City size in boxes")->check(CLI::PositiveNumber);
  cmd->add_option("--sample", a.sample, "Instants computed, spread over the year")->check(CLI::PositiveNumber);
  cmd->add_flag("--baseline", a.baseline,
                       "Also compute the sampled instants one compute(light) call each, and compare (time and values)");
  cmd->add_option("--threads", a.threads, "Threads")->check(CLI::PositiveNumber);
  cmd->add_option("--latitude", a.latitude, "Site latitude (degrees)")->check(CLI::Range(-66.0, 66.0));
  cmd->add_option("--arithmetic", a.arithmetic, "exact, fast or both")
      ->check(CLI::IsMember({"exact", "fast", "both"}));
  cmd->add_flag("--no-ground", a.no_ground, "The ground casts but does not receive (how much of the time is its one union)");
  cmd->add_option("--sun-path", a.sun_path, "spa (the library's solar position, clock time) or solar-time (a simple model)")
      ->check(CLI::IsMember({"spa", "solar-time"}));
  cmd->add_option("--runs", a.runs,
                  "The sample as this many runs of consecutive instants spread over the year (default: every instant alone)");
  return cmd;
}

CLI::App* add_planes_command(CLI::App& app, PlanesArgs& a) {
  CLI::App* cmd = app.add_subcommand(
      "planes", "Blinn plane shadows of the city on its ground plane: wall and CPU time (compute_plane_shadows)");
  cmd->add_option("--sizes", a.sizes, "City sizes in boxes")->delimiter(',')->check(CLI::PositiveNumber);
  cmd->add_option("--elevations", a.elevations, "Sun elevations (degrees)")->delimiter(',')->check(CLI::Range(1.0, 90.0));
  cmd->add_option("--threads", a.threads, "Thread counts")->delimiter(',')->check(CLI::PositiveNumber);
  cmd->add_option("--repeat", a.repeat, "Runs per row; the fastest is kept")->check(CLI::PositiveNumber);
  cmd->add_option("--label", a.label, "Text of the table's first column (which build this is)");
  return cmd;
}

CLI::App* add_low_command(CLI::App& app, LowSunArgs& a) {
  CLI::App* cmd = app.add_subcommand(
      "low-sun", "One sun on the city, exact and fast side by side (areas only): wall, CPU time and peak memory");
  cmd->add_option("--sizes", a.sizes, "City sizes in boxes")->delimiter(',')->check(CLI::PositiveNumber);
  cmd->add_option("--elevations", a.elevations, "Sun elevations (degrees)")->delimiter(',')->check(CLI::Range(1.0, 90.0));
  cmd->add_option("--arithmetic", a.arithmetics, "exact, fast or both, in this order")
      ->delimiter(',')
      ->check(CLI::IsMember({"exact", "fast"}));
  cmd->add_option("--threads", a.threads, "Thread counts")->delimiter(',')->check(CLI::PositiveNumber);
  cmd->add_option("--label", a.label, "Text of the table's first column (which build this is)");
  return cmd;
}

CLI::App* add_tiles_command(CLI::App& app, TilesArgs& a) {
  CLI::App* cmd = app.add_subcommand(
      "tiles", "Large receivers split into tiles: the longest work item's share, 1 and 2 threads, same bits as untiled");
  cmd->add_option("--sizes", a.sizes, "City sizes in boxes")->delimiter(',')->check(CLI::PositiveNumber);
  cmd->add_option("--elevations", a.elevations, "Sun elevations (degrees)")->delimiter(',')->check(CLI::Range(1.0, 90.0));
  cmd->add_option("--arithmetic", a.arithmetics, "exact, fast or both, in this order")
      ->delimiter(',')
      ->check(CLI::IsMember({"exact", "fast"}));
  cmd->add_option("--threads", a.threads, "Thread counts")->delimiter(',')->check(CLI::PositiveNumber);
  cmd->add_option("--tile-casters", a.casters, "ShadowOptions::tile_casters for the tiled rows");
  cmd->add_option("--fast-tile-casters", a.fast_casters, "ShadowOptions::fast_tile_casters for the tiled rows");
  cmd->add_flag("--no-untiled", a.no_untiled, "Leave out the untiled rows");
  cmd->add_option("--grounds", a.grounds, "The city's ground: rectangle, octagon (corners cut), rotated (30 degrees)")
      ->delimiter(',')
      ->check(CLI::IsMember({"rectangle", "octagon", "rotated"}));
  return cmd;
}

CLI::App* add_comb_command(CLI::App& app, CombArgs& a) {
  CLI::App* cmd = app.add_subcommand(
      "comb", "One comb-shaped face (4 vertices a tooth) 1 m above a ground it shadows: large single faces");
  cmd->add_option("--teeth", a.teeth, "Teeth (the face has 4 x teeth + 3 vertices)")->check(CLI::PositiveNumber);
  cmd->add_flag("--areas-only", a.areas_only, "Compute areas only (no fragment polygons)");
  cmd->add_flag("--lamp", a.lamp,
                     "Issue 30's scene instead: a 20 x 20 m ground, the comb scaled into 16 x 16 m 1 m above "
                     "it, a sun and a point lamp over it (--threads, --lamp-height)");
  cmd->add_option("--threads", a.threads, "With --lamp: worker threads (default 2)");
  cmd->add_option("--lamp-height", a.lamp_height,
                       "With --lamp: the lamp's height (default 6: the shadow stays on the ground; 3: it leaves it)")
      ->check(CLI::Range(1.5, 1e6));
  return cmd;
}

}  // namespace bench
