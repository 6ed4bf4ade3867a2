// SPDX-License-Identifier: GPL-3.0-or-later
// shadow-bench: times the exact engine on procedurally generated scenes.
//
// Each case runs in a forked child so that its peak memory (ru_maxrss) is its own. Output: a
// Markdown table on stdout and, with --csv FILE, the same rows as CSV.
// `shadow-bench compare` runs the exact engine against the sampled baselines (speed against
// error) and `shadow-bench hard-cases` the hard cases through every method: bench_compare.cpp.
#include "bench_compare.hpp"
#include "bench_soft.hpp"
#include "bench_light_visibility.hpp"
#include "bench_prepare.hpp"

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

namespace {

struct Case {
  std::string scene;   // "city", "city-fixed", "room", "city-plane" (plane shadows only)
  std::size_t size;    // boxes or tables
  double extent;       // city side (m)
  std::string light;   // description
  double elevation;    // sun elevation (deg) for cities
};

struct Measurement {
  double prepare_s = 0, compute_s = 0;
  long peak_kib = 0;
  std::size_t faces = 0;
  shadow::ShadowStats stats;
  double lit_fraction = 0;
  bool ok = false;
};

shadow::Scene build(const Case& c) {
  if (c.scene == "room") return shadow::make_furnished_room(c.size, 11);
  shadow::Scene scene = shadow::make_city(c.size, c.extent, 2026);
  scene.lights.push_back(shadow::directional_light("sun", shadow::sun_direction(c.elevation, 135.0)));
  if (c.scene == "city-plane") scene.planes.push_back({"ground", {0, 0, 0}, {0, 0, 1}});
  return scene;
}

/// Runs a case `repeat` times and keeps the fastest time of each phase: on a shared machine
/// the minimum is the least disturbed measurement.
Measurement run_case(const Case& c, unsigned threads, bool polygons, int repeat) {
  using Clock = std::chrono::steady_clock;
  Measurement m;
  shadow::Scene scene = build(c);
  shadow::validate_scene(scene);
  m.faces = scene.faces.size();
  shadow::ShadowResult result;
  m.prepare_s = m.compute_s = 1e300;
  for (int r = 0; r < repeat; ++r) {
    const auto t0 = Clock::now();
    const shadow::ShadowEngine engine(scene);
    const auto t1 = Clock::now();
    shadow::ShadowOptions options;
    options.threads = threads;
    options.polygons = polygons;
    if (c.scene == "city-plane") {
      result.plane_shadows = shadow::compute_plane_shadows(scene, options);
    } else {
      result = engine.compute(options);
    }
    const auto t2 = Clock::now();
    m.prepare_s = std::min(m.prepare_s, std::chrono::duration<double>(t1 - t0).count());
    m.compute_s = std::min(m.compute_s, std::chrono::duration<double>(t2 - t1).count());
  }
  m.stats = result.stats;
  double area = 0, lit = 0;
  for (const shadow::FaceLighting& fl : result.lighting) {
    area += fl.area;
    lit += fl.lit_area;
  }
  m.lit_fraction = area > 0 ? lit / area : 0;
  // Plane shadows: report the shadowed fraction of the city's ground square instead.
  if (!result.plane_shadows.empty()) m.lit_fraction = result.plane_shadows[0].area / ((c.extent + 20) * (c.extent + 20));
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  m.peak_kib = usage.ru_maxrss;
  m.ok = true;
  return m;
}

/// Runs a case in a child process and reads its measurement back through a pipe.
Measurement run_isolated(const Case& c, unsigned threads, bool polygons, int repeat) {
  int fds[2];
  if (pipe(fds) != 0) return run_case(c, threads, polygons, repeat);
  const pid_t pid = fork();
  if (pid == 0) {
    close(fds[0]);
    Measurement m = run_case(c, threads, polygons, repeat);
    std::ostringstream out;
    out.precision(17);
    out << m.prepare_s << ' ' << m.compute_s << ' ' << m.peak_kib << ' ' << m.faces << ' '
        << m.stats.receivers << ' ' << m.stats.back_facing << ' ' << m.stats.candidate_pairs << ' '
        << m.stats.casting_pairs << ' ' << m.stats.unshadowed << ' ' << m.lit_fraction;
    const std::string text = out.str();
    if (write(fds[1], text.data(), text.size()) < 0) _exit(1);
    _exit(0);
  }
  close(fds[1]);
  std::string text;
  char buffer[512];
  ssize_t n;
  while ((n = read(fds[0], buffer, sizeof buffer)) > 0) text.append(buffer, static_cast<std::size_t>(n));
  close(fds[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  Measurement m;
  std::istringstream in(text);
  in >> m.prepare_s >> m.compute_s >> m.peak_kib >> m.faces >> m.stats.receivers >>
      m.stats.back_facing >> m.stats.candidate_pairs >> m.stats.casting_pairs >> m.stats.unshadowed >>
      m.lit_fraction;
  m.ok = WIFEXITED(status) && WEXITSTATUS(status) == 0 && !in.fail();
  return m;
}

/// docs/benchmarks.md, "Large single faces": validation and computation on one thread.
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

/// docs/benchmarks.md, "A comb under a lamp" (issue 30): a 20 x 20 m ground, the comb of `teeth`
/// teeth scaled into the square [2, 18]^2 1 m above it, a sun and a point lamp at (10.25, 9.75,
/// lamp_height) over it. The time of the whole run (validation, both lights) and of each light
/// alone; the ground's shadow areas against the comb's area (the sun's shadow a translated copy,
/// the lamp's scaled by h / (h - 1) when it stays on the ground).
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

/// docs/benchmarks.md, "A year of suns": hourly suns of a year at `latitude`, of which `sample`
/// spread over the year are computed with compute_series and (with `baseline`) the same
/// instants one at a time with compute(light); the year is extrapolated from the cost per
/// instant. `sun_path` "spa": what `shadow series` runs, the library's solar position (SPA) at
/// every hour of 2026 in local standard time at longitude 2.35 E (UTC+1), suns above the horizon;
/// "solar-time": a simple model (Cooper's declination, solar time, no refraction), whose noon sun
/// lies in the plane of every east and west wall up to the rounding of its direction (exactly
/// edge-on walls stay on the fast path; those grazed by 1e-17 go to the exact engine), which no
/// clock-time series does.
int run_series_bench(std::size_t boxes, std::size_t sample, bool baseline, unsigned threads,
                     double latitude, const std::string& arithmetic, bool ground, const std::string& sun_path) {
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
  std::vector<shadow::Light> lights;
  for (std::size_t i = 0; i < sample; ++i) lights.push_back(year[i * year.size() / sample]);
  const double extent = 500.0 * std::sqrt(static_cast<double>(boxes) / 1000.0);
  shadow::Scene scene = shadow::make_city(boxes, extent, 2026);
  scene.meshes[0].receiver = ground;  // mesh 0 is the ground (one face)
  shadow::validate_scene(scene);
  const auto t0 = Clock::now();
  const shadow::ShadowEngine engine(scene, threads);
  const double prepare = std::chrono::duration<double>(Clock::now() - t0).count();
  std::printf("city of %zu boxes (%zu faces%s), latitude %.1f, sun path %s: %zu hourly suns above the horizon in a year; "
              "sample of %zu, %u threads, preparation %.3f s\n",
              boxes, scene.faces.size(), ground ? "" : ", ground not receiving", latitude, sun_path.c_str(), year.size(),
              sample, threads, prepare);
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

/// docs/benchmarks.md, "Plane shadows": the city's shadow on its ground plane (Blinn).
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

/// docs/tiles.md: the city at each elevation, untiled and tiled, on 1 and 2 threads: CPU time,
/// the longest work item's share of the items' CPU time, and whether the lit areas are the same
/// bits (a digest of every lit area) as untiled on one thread.
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

/// docs/benchmarks.md, "The fast path at a low sun": one sun on the city at each elevation, exact
/// and fast side by side (areas only), one child process per row.
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

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"shadow-bench: time libshadow's exact engine on generated cities and rooms"};
  std::vector<std::size_t> sizes{100, 1000, 10000};
  std::vector<unsigned> threads{1, 2};
  std::string csv_path;
  bool areas_only = false;
  bool quick = false;
  int repeat = 3;
  app.add_option("--sizes", sizes, "City sizes in boxes")->delimiter(',');
  app.add_option("--threads", threads, "Thread counts to run")->delimiter(',');
  app.add_option("--csv", csv_path, "Also write the rows as CSV to this file");
  app.add_flag("--areas-only", areas_only, "Compute areas only (no fragment polygons)");
  app.add_option("--repeat", repeat, "Runs per case below 10,000 boxes; the fastest is kept")->check(CLI::PositiveNumber);
  app.add_flag("--quick", quick, "Only the 100- and 1,000-box cities at 40 degrees (smoke run)");

  bench::CompareOptions compare;
  CLI::App* compare_cmd = app.add_subcommand(
      "compare", "Exact against the baselines (shadow map, ray sampling): time, memory, error");
  compare_cmd->add_option("--sizes", compare.sizes, "City sizes in boxes")->delimiter(',');
  compare_cmd->add_option("--threads", compare.threads, "Threads for every method")->check(CLI::PositiveNumber);
  compare_cmd->add_option("--csv", compare.csv_path, "Write the rows as CSV to this file");
  compare_cmd->add_option("--json", compare.json_path, "Write the rows as JSON to this file");
  compare_cmd->add_option("--max-samples", compare.max_samples, "Skip ray spacings that cast more rays");
  compare_cmd->add_option("--methods", compare.only_methods, "Only these baselines (exact always runs)")->delimiter(',');
  compare_cmd->add_option("--scenes", compare.only_scenes, "Only these scenes (names as in the table)")->delimiter(',');
  compare_cmd->add_option("--spacings", compare.spacings, "Ray-sampling spacings (m) for every scene")->delimiter(',');
  compare_cmd->add_option("--resolutions", compare.resolutions, "Shadow-map resolutions")->delimiter(',');
  compare_cmd->add_option("--constant-bias", compare.constant_bias, "Shadow-map constant depth bias (m)");
  compare_cmd->add_option("--slope-bias", compare.slope_bias, "Shadow-map slope-scaled bias (texels)");
  compare_cmd->add_option("--max-error", compare.max_error,
                          "Fail (exit 1) when the fast path leaves its error bound on any face (exact is the reference), or a sampled "
                          "baseline's total lit rel. error or mean face error exceeds this")
      ->check(CLI::NonNegativeNumber);
  compare_cmd->add_flag("--quick", compare.quick, "Smoke run: 100-box city and the room, two parameters each");
  unsigned hard_threads = 2;
  std::string hard_csv;
  CLI::App* hard_cmd = app.add_subcommand("hard-cases", "The hard cases of the design notes through every method");
  hard_cmd->add_option("--threads", hard_threads, "Threads for every method")->check(CLI::PositiveNumber);
  hard_cmd->add_option("--csv", hard_csv, "Write the rows as CSV to this file");
  bool hard_quick = false;
  hard_cmd->add_flag("--quick", hard_quick, "Shadow maps at 256 and 1024 instead of 1024 and 4096");
  std::string golden_output, golden_check, golden_dir;
  bool golden_quick = false;
  unsigned golden_threads = 2;
  CLI::App* golden_cmd = app.add_subcommand(
      "golden", "Areas of the benchmark scenes, hard cases and example, bit for bit, as digests (exact and fast)");
  golden_cmd->add_option("--output", golden_output, "Write the digests to this file");
  golden_cmd->add_option("--check", golden_check, "Compare with digests written earlier; exit 1 on a difference");
  golden_cmd->add_option("--write-dir", golden_dir, "Also write every value, one file per case, into this folder");
  golden_cmd->add_option("--threads", golden_threads, "Threads (results do not depend on it)")->check(CLI::PositiveNumber);
  golden_cmd->add_flag("--quick", golden_quick, "Leave out the 1,000-box city; 10 spheres instead of 50");
  std::size_t series_boxes = 1000, series_sample = 100;
  bool series_baseline = false;
  unsigned series_threads = 2;
  double series_latitude = 48.0;
  std::string series_arithmetic = "both";
  bool series_no_ground = false;
  CLI::App* series_cmd = app.add_subcommand(
      "series", "A year of hourly suns on a city, areas only: a sample of instants, extrapolated to the year");
  series_cmd->add_option("--boxes", series_boxes, "City size in boxes")->check(CLI::PositiveNumber);
  series_cmd->add_option("--sample", series_sample, "Instants computed, spread over the year")->check(CLI::PositiveNumber);
  series_cmd->add_flag("--baseline", series_baseline,
                       "Also compute the sampled instants one compute(light) call each, and compare (time and values)");
  series_cmd->add_option("--threads", series_threads, "Threads")->check(CLI::PositiveNumber);
  series_cmd->add_option("--latitude", series_latitude, "Site latitude (degrees)")->check(CLI::Range(-66.0, 66.0));
  series_cmd->add_option("--arithmetic", series_arithmetic, "exact, fast or both")
      ->check(CLI::IsMember({"exact", "fast", "both"}));
  series_cmd->add_flag("--no-ground", series_no_ground, "The ground casts but does not receive (how much of the time is its one union)");
  std::string series_sun_path = "spa";
  series_cmd->add_option("--sun-path", series_sun_path, "spa (the library's solar position, clock time) or solar-time (a simple model)")
      ->check(CLI::IsMember({"spa", "solar-time"}));
  std::size_t comb_teeth = 10000;
  bool comb_areas_only = false;
  CLI::App* comb_cmd = app.add_subcommand(
      "comb", "One comb-shaped face (4 vertices a tooth) 1 m above a ground it shadows: large single faces");
  comb_cmd->add_option("--teeth", comb_teeth, "Teeth (the face has 4 x teeth + 3 vertices)")->check(CLI::PositiveNumber);
  comb_cmd->add_flag("--areas-only", comb_areas_only, "Compute areas only (no fragment polygons)");
  bool comb_lamp = false;
  unsigned comb_threads = 2;
  double comb_lamp_height = 6;
  comb_cmd->add_flag("--lamp", comb_lamp,
                     "Issue 30's scene instead: a 20 x 20 m ground, the comb scaled into 16 x 16 m 1 m above "
                     "it, a sun and a point lamp over it (--threads, --lamp-height)");
  comb_cmd->add_option("--threads", comb_threads, "With --lamp: worker threads (default 2)");
  comb_cmd->add_option("--lamp-height", comb_lamp_height,
                       "With --lamp: the lamp's height (default 6: the shadow stays on the ground; 3: it leaves it)")
      ->check(CLI::Range(1.5, 1e6));
  std::size_t sun_boxes = 10;
  std::vector<std::size_t> sun_instants{24, 96};
  unsigned sun_threads = 2;
  std::string sun_write;
  CLI::App* sun_cmd = app.add_subcommand(
      "sun-hours", "The exact sun-hours map of a generated city over an equinox day, against the per-instant engine");
  sun_cmd->add_option("--boxes", sun_boxes, "Boxes in the city")->check(CLI::PositiveNumber);
  sun_cmd->add_option("--instants", sun_instants, "Instants over the day (12 h of daylight split evenly)")
      ->delimiter(',')
      ->check(CLI::PositiveNumber);
  sun_cmd->add_option("--threads", sun_threads, "Threads")->check(CLI::PositiveNumber);
  sun_cmd->add_option("--write", sun_write, "Write the ground's map (first instant count) as DIR/sun_hours.vtp, and the city");
  std::vector<std::size_t> planes_sizes{10000};
  std::vector<double> planes_elevations{40.0, 5.0};
  std::vector<unsigned> planes_threads{1, 2};
  int planes_repeat = 1;
  std::string planes_label = "this";
  CLI::App* planes_cmd = app.add_subcommand(
      "planes", "Blinn plane shadows of the city on its ground plane: wall and CPU time (compute_plane_shadows)");
  planes_cmd->add_option("--sizes", planes_sizes, "City sizes in boxes")->delimiter(',')->check(CLI::PositiveNumber);
  planes_cmd->add_option("--elevations", planes_elevations, "Sun elevations (degrees)")->delimiter(',')->check(CLI::Range(1.0, 90.0));
  planes_cmd->add_option("--threads", planes_threads, "Thread counts")->delimiter(',')->check(CLI::PositiveNumber);
  planes_cmd->add_option("--repeat", planes_repeat, "Runs per row; the fastest is kept")->check(CLI::PositiveNumber);
  planes_cmd->add_option("--label", planes_label, "Text of the table's first column (which build this is)");
  bench::SoftOptions soft;
  CLI::App* soft_cmd = app.add_subcommand(
      "soft", "Soft shadows of extended lights: PCF, PCSS and k rays per point against the exact visible fraction");
  soft_cmd->add_option("--threads", soft.threads, "Threads for every method")->check(CLI::PositiveNumber);
  soft_cmd->add_option("--csv", soft.csv_path, "Write the rows as CSV to this file");
  soft_cmd->add_option("--scenes", soft.only_scenes, "Only these scenes (luminaire, sun-city, room-disk)")->delimiter(',');
  soft_cmd->add_option("--reference-rays", soft.reference_rays, "Rays a point of the ray cross-check against the exact fractions")
      ->check(CLI::PositiveNumber);
  soft_cmd->add_option("--max-error", soft.max_error,
                       "Fail (exit 1) when the ray cross-check's mean error exceeds this, rays do not improve with k, "
                       "or a visibility leaves [0, 1]")
      ->check(CLI::NonNegativeNumber);
  soft_cmd->add_flag("--quick", soft.quick, "Smoke run: a small luminaire scene, two settings a method");
  std::size_t vis_boxes = 200, vis_points = 2000;
  unsigned vis_threads = 2;
  CLI::App* vis_cmd = app.add_subcommand(
      "light-visibility", "The exact visible fraction of extended lights at ground points of a city (area_lights.hpp)");
  vis_cmd->add_option("--boxes", vis_boxes, "Boxes in the city")->check(CLI::PositiveNumber);
  vis_cmd->add_option("--points", vis_points, "Ground points")->check(CLI::PositiveNumber);
  vis_cmd->add_option("--threads", vis_threads, "Most threads (1, 2, 4, ... up to it)")->check(CLI::PositiveNumber);
  std::vector<std::size_t> prepare_sizes{10000, 166667};
  std::vector<unsigned> prepare_threads{1, 2};
  int prepare_repeat = 1;
  CLI::App* prepare_cmd = app.add_subcommand(
      "prepare", "Validation and the convex-solid search on the city, against the reference implementations");
  prepare_cmd->add_option("--sizes", prepare_sizes, "City sizes in boxes")->delimiter(',')->check(CLI::PositiveNumber);
  prepare_cmd->add_option("--threads", prepare_threads, "Thread counts")->delimiter(',')->check(CLI::PositiveNumber);
  prepare_cmd->add_option("--repeat", prepare_repeat, "Runs per row; the fastest is kept")->check(CLI::PositiveNumber);
  bool prepare_new_only = false;
  prepare_cmd->add_flag("--new-only", prepare_new_only, "Leave the reference implementations out (for profiling)");
  std::vector<std::size_t> low_sizes{10000};
  std::vector<double> low_elevations{5.0, 40.0};
  std::vector<std::string> low_arithmetics{"exact", "fast"};
  std::vector<unsigned> low_threads{1};
  std::string low_label = "this";
  CLI::App* low_cmd = app.add_subcommand(
      "low-sun", "One sun on the city, exact and fast side by side (areas only): wall, CPU time and peak memory");
  low_cmd->add_option("--sizes", low_sizes, "City sizes in boxes")->delimiter(',')->check(CLI::PositiveNumber);
  low_cmd->add_option("--elevations", low_elevations, "Sun elevations (degrees)")->delimiter(',')->check(CLI::Range(1.0, 90.0));
  low_cmd->add_option("--arithmetic", low_arithmetics, "exact, fast or both, in this order")
      ->delimiter(',')
      ->check(CLI::IsMember({"exact", "fast"}));
  low_cmd->add_option("--threads", low_threads, "Thread counts")->delimiter(',')->check(CLI::PositiveNumber);
  low_cmd->add_option("--label", low_label, "Text of the table's first column (which build this is)");
  std::vector<std::size_t> tiles_sizes{10000};
  std::vector<double> tiles_elevations{40.0, 5.0};
  std::vector<std::string> tiles_arithmetics{"exact", "fast"};
  std::vector<unsigned> tiles_threads{1, 2};
  std::size_t tiles_casters = shadow::ShadowOptions{}.tile_casters;
  std::size_t tiles_fast_casters = shadow::ShadowOptions{}.fast_tile_casters;
  bool tiles_no_untiled = false;
  std::vector<std::string> tiles_grounds{"rectangle"};
  CLI::App* tiles_cmd = app.add_subcommand(
      "tiles", "Large receivers split into tiles: the longest work item's share, 1 and 2 threads, same bits as untiled");
  tiles_cmd->add_option("--sizes", tiles_sizes, "City sizes in boxes")->delimiter(',')->check(CLI::PositiveNumber);
  tiles_cmd->add_option("--elevations", tiles_elevations, "Sun elevations (degrees)")->delimiter(',')->check(CLI::Range(1.0, 90.0));
  tiles_cmd->add_option("--arithmetic", tiles_arithmetics, "exact, fast or both, in this order")
      ->delimiter(',')
      ->check(CLI::IsMember({"exact", "fast"}));
  tiles_cmd->add_option("--threads", tiles_threads, "Thread counts")->delimiter(',')->check(CLI::PositiveNumber);
  tiles_cmd->add_option("--tile-casters", tiles_casters, "ShadowOptions::tile_casters for the tiled rows");
  tiles_cmd->add_option("--fast-tile-casters", tiles_fast_casters, "ShadowOptions::fast_tile_casters for the tiled rows");
  tiles_cmd->add_flag("--no-untiled", tiles_no_untiled, "Leave out the untiled rows");
  tiles_cmd->add_option("--grounds", tiles_grounds, "The city's ground: rectangle, octagon (corners cut), rotated (30 degrees)")
      ->delimiter(',')
      ->check(CLI::IsMember({"rectangle", "octagon", "rotated"}));
  std::size_t city_boxes = 200;
  double city_diameter = 0.53;
  unsigned city_threads = 1;
  CLI::App* city_cmd = app.add_subcommand(
      "area-city", "ShadowEngine::compute for a city under a sun disk: regions and fragment visibility (docs/area-lights.md)");
  city_cmd->add_option("--boxes", city_boxes, "Boxes in the city")->check(CLI::PositiveNumber);
  city_cmd->add_option("--diameter", city_diameter, "The sun's angular diameter (degrees)")->check(CLI::PositiveNumber);
  city_cmd->add_option("--threads", city_threads, "Threads")->check(CLI::PositiveNumber);
  app.require_subcommand(0, 1);
  CLI11_PARSE(app, argc, argv);
  if (compare_cmd->parsed()) return bench::run_compare(compare);
  if (soft_cmd->parsed()) return bench::run_soft(soft);
  if (tiles_cmd->parsed())
    return run_tiles_bench(tiles_sizes, tiles_elevations, tiles_arithmetics, tiles_threads, tiles_casters,
                           tiles_fast_casters, !tiles_no_untiled, tiles_grounds);
  if (low_cmd->parsed()) return run_low_sun_bench(low_sizes, low_elevations, low_arithmetics, low_threads, low_label);
  if (planes_cmd->parsed()) return run_planes_bench(planes_sizes, planes_elevations, planes_threads, planes_repeat, planes_label);
  if (hard_cmd->parsed()) return bench::run_hard_cases(hard_threads, hard_csv, hard_quick);
  if (comb_cmd->parsed())
    return comb_lamp ? run_comb_lamp(comb_teeth, !comb_areas_only, comb_threads, comb_lamp_height)
                     : run_comb(comb_teeth, !comb_areas_only);
  if (sun_cmd->parsed()) return bench::run_sun_hours(sun_boxes, sun_instants, sun_threads, sun_write);
  if (city_cmd->parsed()) return bench::run_area_city(city_boxes, city_diameter, city_threads);
  if (vis_cmd->parsed()) return bench::run_light_visibility(vis_boxes, vis_points, vis_threads);
  if (prepare_cmd->parsed()) return bench::run_prepare(prepare_sizes, prepare_threads, prepare_repeat, prepare_new_only);
  if (golden_cmd->parsed())
    return bench::run_golden(LIBSHADOW_SOURCE_DIR, golden_output, golden_check, golden_dir, golden_quick, golden_threads);
  if (series_cmd->parsed())
    return run_series_bench(series_boxes, series_sample, series_baseline, series_threads, series_latitude,
                            series_arithmetic, !series_no_ground, series_sun_path);

  std::vector<Case> cases;
  // Constant density: 1,000 boxes on 500 m x 500 m; the side grows with sqrt(N).
  for (std::size_t n : sizes) {
    if (quick && n > 1000) continue;
    const double extent = 500.0 * std::sqrt(static_cast<double>(n) / 1000.0);
    for (double elevation : {40.0, 5.0}) {
      if (quick && elevation != 40.0) continue;
      cases.push_back({"city", n, extent, "sun " + std::to_string(static_cast<int>(elevation)) + " deg", elevation});
    }
  }
  if (!quick) {
    // Fixed extent: shadows pile up as N grows.
    for (std::size_t n : sizes) cases.push_back({"city-fixed", n, 500.0, "sun 40 deg", 40.0});
    cases.push_back({"room", 12, 0, "ceiling lamp", 0});
    // Blinn plane shadows of the whole city on the ground plane (the "lit fraction" column then
    // holds the shadow area over the ground square's area).
    for (std::size_t n : sizes)
      cases.push_back({"city-plane", n, 500.0 * std::sqrt(static_cast<double>(n) / 1000.0), "sun 40 deg", 40.0});
  }

  std::ofstream csv;
  if (!csv_path.empty()) {
    csv.open(csv_path);
    csv << "scene,size,extent_m,light,faces,threads,prepare_s,compute_s,peak_mib,receivers,back_facing,"
           "candidate_pairs,casting_pairs,unshadowed,lit_fraction\n";
  }
  std::printf("| scene | boxes/tables | extent (m) | light | faces | threads | prepare (s) | compute (s) | peak (MiB) | candidate pairs | casting pairs | lit fraction |\n");
  std::printf("|---|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (const Case& c : cases) {
    for (unsigned t : threads) {
      const Measurement m = run_isolated(c, t, !areas_only, c.size >= 10000 ? 1 : repeat);
      if (!m.ok) {
        std::printf("| %s | %zu | %.0f | %s | - | %u | failed |\n", c.scene.c_str(), c.size, c.extent, c.light.c_str(), t);
        continue;
      }
      std::printf("| %s | %zu | %.0f | %s | %zu | %u | %.3f | %.3f | %.0f | %llu | %llu | %.6f |\n", c.scene.c_str(),
                  c.size, c.extent, c.light.c_str(), m.faces, t, m.prepare_s, m.compute_s, m.peak_kib / 1024.0,
                  static_cast<unsigned long long>(m.stats.candidate_pairs),
                  static_cast<unsigned long long>(m.stats.casting_pairs), m.lit_fraction);
      std::fflush(stdout);
      if (csv.is_open())
        csv << c.scene << ',' << c.size << ',' << c.extent << ',' << c.light << ',' << m.faces << ',' << t << ','
            << m.prepare_s << ',' << m.compute_s << ',' << m.peak_kib / 1024.0 << ',' << m.stats.receivers << ','
            << m.stats.back_facing << ',' << m.stats.candidate_pairs << ',' << m.stats.casting_pairs << ','
            << m.stats.unshadowed << ',' << m.lit_fraction << '\n';
    }
  }
  return 0;
}
