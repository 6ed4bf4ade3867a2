// SPDX-License-Identifier: GPL-3.0-or-later
// shadow-bench compare: the exact engine and every baseline on the standard scenes. The exact
// result of each scene is computed once (in its own child) and is the reference for the others.
#include "bench_compare.hpp"

#include <shadow/baselines.hpp>
#include <shadow/shadow.hpp>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

namespace bench {

namespace {

/// The engine (preparation + one computation of every light, areas only, like the baselines)
/// in the given arithmetic.
MethodRun run_engine(const shadow::Scene& scene, unsigned threads, shadow::Arithmetic arithmetic) {
  using Clock = std::chrono::steady_clock;
  MethodRun r;
  const auto t0 = Clock::now();
  const shadow::ShadowEngine engine(scene, threads);
  const auto t1 = Clock::now();
  shadow::ShadowOptions options;
  options.threads = threads;
  options.polygons = false;
  options.arithmetic = arithmetic;
  r.lighting = engine.compute(options).lighting;
  r.prepare_s = std::chrono::duration<double>(t1 - t0).count();
  r.compute_s = std::chrono::duration<double>(Clock::now() - t1).count();
  return r;
}

std::vector<double> no_parameter(const std::vector<double>&, const std::vector<double>&, bool) { return {0}; }

}  // namespace

std::vector<Method> methods(const CompareOptions& o) {
  std::vector<Method> out;
  out.push_back({"exact", "", no_parameter, [](const shadow::Scene& scene, double, unsigned threads) {
                   return run_engine(scene, threads, shadow::Arithmetic::Exact);
                 }});
  // The fast path (Arithmetic::Fast): the engine's pipeline in doubles, unions on an integer
  // grid, each face's lit area with a certified error bound; the preparation is the engine's.
  out.push_back({"fast", "", no_parameter, [](const shadow::Scene& scene, double, unsigned threads) {
                   return run_engine(scene, threads, shadow::Arithmetic::Fast);
                 }});
  out.push_back({"shadow-map", "resolution",
                 [](const std::vector<double>&, const std::vector<double>& resolutions, bool quick) {
                   if (!resolutions.empty()) return resolutions;
                   return quick ? std::vector<double>{256, 1024}
                                : std::vector<double>{256, 512, 1024, 2048, 4096, 8192};
                 },
                 [cb = o.constant_bias, sb = o.slope_bias](const shadow::Scene& scene, double resolution,
                                                           unsigned threads) {
                   shadow::ShadowMapOptions options;
                   options.resolution = static_cast<int>(resolution);
                   options.constant_bias = cb;
                   options.slope_bias = sb;
                   options.threads = threads;
                   shadow::BaselineResult b = shadow::shadow_map_lighting(scene, options);
                   return MethodRun{std::move(b.lighting), b.prepare_seconds, b.compute_seconds, b.samples};
                 }});
  out.push_back({"ray-sampling", "spacing_m",
                 [](const std::vector<double>& spacings, const std::vector<double>&, bool quick) {
                   if (!quick) return spacings;
                   return std::vector<double>(spacings.begin(), spacings.begin() + std::min<std::size_t>(2, spacings.size()));
                 },
                 [](const shadow::Scene& scene, double spacing, unsigned threads) {
                   shadow::RaySamplingOptions options;
                   options.spacing = spacing;
                   options.threads = threads;
                   shadow::BaselineResult b = shadow::ray_sampling_lighting(scene, options);
                   return MethodRun{std::move(b.lighting), b.prepare_seconds, b.compute_seconds, b.samples};
                 }});
  return out;
}

namespace {

struct BenchScene {
  std::string name;   // table name, e.g. "city-1000 sun 40"
  std::string kind;   // city, room, spheres
  std::size_t size;   // boxes, tables, spheres
  std::string light;
  std::vector<double> spacings;  // ray-sampling spacings (m), coarse to fine
  std::function<shadow::Scene()> build;
};

std::vector<BenchScene> standard_scenes(const CompareOptions& o) {
  std::vector<BenchScene> out;
  for (std::size_t n : o.sizes) {
    if (o.quick && n > 100) continue;
    // Constant density: 1,000 boxes on 500 m; the side grows with sqrt(N) (as the scaling bench).
    const double extent = 500.0 * std::sqrt(static_cast<double>(n) / 1000.0);
    for (double elevation : {40.0, 5.0}) {
      if (o.quick && elevation != 40.0) continue;
      const std::string light = "sun " + std::to_string(static_cast<int>(elevation));
      out.push_back({"city-" + std::to_string(n) + " " + light, "city", n, light,
                     {2, 1, 0.5, 0.25, 0.1, 0.05, 0.025}, [n, extent, elevation] {
                       shadow::Scene s = shadow::make_city(n, extent, 2026);
                       s.lights.push_back(shadow::directional_light("sun", shadow::sun_direction(elevation, 135.0)));
                       return s;
                     }});
    }
  }
  out.push_back({"room lamp", "room", 12, "ceiling lamp", {0.2, 0.1, 0.05, 0.02, 0.01, 0.005},
                 [] { return shadow::make_furnished_room(12, 11); }});
  if (!o.quick)
    out.push_back({"spheres-50 sun 40", "spheres", 50, "sun 40", {1, 0.5, 0.25, 0.1, 0.05, 0.025}, [] {
                     shadow::Scene s = shadow::make_sphere_field(50, 60, 7);
                     s.lights.push_back(shadow::directional_light("sun", shadow::sun_direction(40, 135.0)));
                     return s;
                   }});
  return out;
}

/// The reference entries of a scene (exact), as the parent keeps them.
struct Reference {
  std::vector<shadow::FaceLighting> lighting;
  double receiving_area = 0;  // sum of receiving face areas (front-facing or not)
  double front_area = 0;      // sum of front-facing receiving face areas (rays are cast from those)
};

/// One table row; a POD so that a child can send it through a pipe as bytes.
struct Row {
  double parameter = 0;
  double prepare_s = 0, compute_s = 0, total_s = 0, peak_mib = 0;
  double lit_fraction = 0;  // total lit area / total receiving area
  double total_rel_error = 0, mean_abs_error = 0, max_abs_error = 0;
  std::uint64_t samples = 0;
  std::uint64_t faces = 0;
  std::uint64_t beyond_bound = 0;  // entries outside their own certified bound (Errors::beyond_bound)
  int ok = 0;
  char error[160] = {};
};

}  // namespace

Errors compare(const std::vector<shadow::FaceLighting>& got, const std::vector<shadow::FaceLighting>& ref) {
  Errors e;
  double area = 0, lit = 0, ref_lit = 0, sum_abs = 0;
  std::size_t counted = 0;
  std::size_t j = 0;
  for (const shadow::FaceLighting& r : ref) {
    // Both are sorted by (face, light); a missing entry counts as unlit.
    while (j < got.size() && std::make_pair(got[j].face_id, got[j].light_id) < std::make_pair(r.face_id, r.light_id)) ++j;
    const bool have = j < got.size() && got[j].face_id == r.face_id && got[j].light_id == r.light_id;
    const double g_lit = have ? got[j].lit_area : 0.0, g_frac = have ? got[j].lit_fraction : 0.0;
    const double g_bound = have ? got[j].lit_area_error_bound : 0.0;
    // Both lit areas are rounded once from exact values: allow those two roundings.
    if (!(std::abs(g_lit - r.lit_area) <= g_bound + 2.3e-16 * r.area)) ++e.beyond_bound;
    area += r.area;
    lit += g_lit;
    ref_lit += r.lit_area;
    if (r.area > 0) {
      const double d = std::abs(g_frac - r.lit_fraction);
      sum_abs += d;
      e.max_abs = std::max(e.max_abs, d);
      ++counted;
    }
  }
  e.lit_fraction = area > 0 ? lit / area : 0;
  e.total_rel = ref_lit > 0 ? std::abs(lit - ref_lit) / ref_lit : std::abs(lit);
  e.mean_abs = counted ? sum_abs / static_cast<double>(counted) : 0;
  return e;
}

namespace {

bool read_all(int fd, void* data, std::size_t size) {
  auto* p = static_cast<char*>(data);
  while (size > 0) {
    const ssize_t n = read(fd, p, size);
    if (n <= 0) return false;
    p += n;
    size -= static_cast<std::size_t>(n);
  }
  return true;
}

bool write_all(int fd, const void* data, std::size_t size) {
  const auto* p = static_cast<const char*>(data);
  while (size > 0) {
    const ssize_t n = write(fd, p, size);
    if (n <= 0) return false;
    p += n;
    size -= static_cast<std::size_t>(n);
  }
  return true;
}

/// Runs `method` with `parameter` on the scene in a forked child (its own peak memory). When
/// `reference` is null the child also sends its lighting back (it is the reference run).
Row run_isolated(const BenchScene& bs, const Method& method, double parameter, unsigned threads,
                 const Reference* reference, Reference* out_reference) {
  Row row;
  row.parameter = parameter;
  int fds[2];
  if (pipe(fds) != 0) {
    std::snprintf(row.error, sizeof row.error, "pipe failed");
    return row;
  }
  std::fflush(stdout);
  std::fflush(stderr);
  const pid_t pid = fork();
  if (pid == 0) {
    close(fds[0]);
    Row r;
    r.parameter = parameter;
    std::vector<shadow::FaceLighting> lighting;
    try {
      shadow::Scene scene = bs.build();
      shadow::validate_scene(scene);
      r.faces = scene.faces.size();
      const auto t0 = std::chrono::steady_clock::now();
      MethodRun m = method.run(scene, parameter, threads);
      r.total_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      r.prepare_s = m.prepare_s;
      r.compute_s = m.compute_s;
      r.samples = m.samples;
      rusage usage{};
      getrusage(RUSAGE_SELF, &usage);
      r.peak_mib = static_cast<double>(usage.ru_maxrss) / 1024.0;
      const Errors e = compare(m.lighting, reference ? reference->lighting : m.lighting);
      r.lit_fraction = e.lit_fraction;
      r.total_rel_error = e.total_rel;
      r.mean_abs_error = e.mean_abs;
      r.max_abs_error = e.max_abs;
      r.beyond_bound = e.beyond_bound;
      r.ok = 1;
      lighting = std::move(m.lighting);
    } catch (const std::exception& ex) {
      std::snprintf(r.error, sizeof r.error, "%s", ex.what());
    }
    bool sent = write_all(fds[1], &r, sizeof r);
    if (!reference) {
      const std::uint64_t n = lighting.size();
      sent = sent && write_all(fds[1], &n, sizeof n) &&
             write_all(fds[1], lighting.data(), lighting.size() * sizeof(shadow::FaceLighting));
    }
    _exit(sent ? 0 : 1);
  }
  close(fds[1]);
  bool got = read_all(fds[0], &row, sizeof row);
  if (got && !reference && out_reference) {
    std::uint64_t n = 0;
    got = read_all(fds[0], &n, sizeof n);
    if (got) {
      out_reference->lighting.resize(n);
      got = read_all(fds[0], out_reference->lighting.data(), n * sizeof(shadow::FaceLighting));
    }
  }
  close(fds[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  if (!got || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    row.ok = 0;
    if (!row.error[0]) std::snprintf(row.error, sizeof row.error, "child failed (status %d)", status);
  }
  return row;
}

std::string json_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out;
}

}  // namespace

int run_compare(const CompareOptions& o) {
  const bool tty = isatty(2) != 0;
  const std::vector<Method> all = methods(o);
  std::vector<BenchScene> scenes = standard_scenes(o);
  if (!o.only_scenes.empty())
    scenes.erase(std::remove_if(scenes.begin(), scenes.end(),
                                [&](const BenchScene& s) {
                                  return std::find(o.only_scenes.begin(), o.only_scenes.end(), s.name) == o.only_scenes.end();
                                }),
                 scenes.end());
  std::ofstream csv, json;
  if (!o.csv_path.empty()) {
    csv.open(o.csv_path);
    csv << "scene,kind,size,faces,light,method,parameter_name,parameter,threads,prepare_s,compute_s,total_s,peak_mib,"
           "samples,lit_fraction,total_lit_rel_error,face_fraction_mean_abs_error,face_fraction_max_abs_error\n";
    csv.precision(10);
  }
  if (!o.json_path.empty()) {
    json.open(o.json_path);
    json << "[\n";
    json.precision(10);
  }
  bool first_json = true;
  std::printf("| scene | faces | method | parameter | prepare (s) | compute (s) | total (s) | peak (MiB) | samples | "
              "lit fraction | total lit rel. error | face error mean | face error max |\n");
  std::printf("|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  int failures = 0;
  for (const BenchScene& bs : scenes) {
    Reference ref;
    std::vector<std::pair<const Method*, double>> runs;
    for (const Method& m : all) {
      if (!o.only_methods.empty() && m.name != "exact" &&
          std::find(o.only_methods.begin(), o.only_methods.end(), m.name) == o.only_methods.end())
        continue;
      for (double p : m.parameters(o.spacings.empty() ? bs.spacings : o.spacings, o.resolutions, o.quick))
        runs.emplace_back(&m, p);
    }
    for (std::size_t k = 0; k < runs.size(); ++k) {
      const Method& m = *runs[k].first;
      const double p = runs[k].second;
      const bool is_reference = m.name == "exact";
      if (m.parameter_name == "spacing_m" && ref.front_area / (p * p) > o.max_samples) continue;  // too slow
      if (tty) std::fprintf(stderr, "\r\033[K%s: %s %g (%zu/%zu)", bs.name.c_str(), m.name.c_str(), p, k + 1, runs.size());
      Row row = run_isolated(bs, m, p, o.threads, is_reference ? nullptr : &ref, is_reference ? &ref : nullptr);
      if (is_reference) {
        for (const shadow::FaceLighting& fl : ref.lighting) {
          ref.receiving_area += fl.area;
          if (fl.faces_light) ref.front_area += fl.area;
        }
      }
      if (!row.ok) {
        ++failures;
        std::printf("| %s | - | %s | %g | failed: %s |\n", bs.name.c_str(), m.name.c_str(), p, row.error);
        if (is_reference) break;  // nothing to compare with
        continue;
      }
      char parameter[32] = "-";
      if (!m.parameter_name.empty()) std::snprintf(parameter, sizeof parameter, "%g", p);
      std::printf("| %s | %llu | %s | %s | %.3f | %.3f | %.3f | %.0f | %llu | %.6f | %.2e | %.2e | %.2e |\n",
                  bs.name.c_str(), static_cast<unsigned long long>(row.faces), m.name.c_str(), parameter, row.prepare_s,
                  row.compute_s, row.total_s, row.peak_mib, static_cast<unsigned long long>(row.samples),
                  row.lit_fraction, row.total_rel_error, row.mean_abs_error, row.max_abs_error);
      std::fflush(stdout);
      if (o.max_error >= 0 && !is_reference) {
        // The fast path certifies every face against the exact reference; the sampled baselines get
        // a threshold. (The exact row is the reference itself: nothing to check here.)
        const bool certified = m.name == "fast";
        std::string problem;
        if (certified && row.beyond_bound > 0)
          problem = std::to_string(row.beyond_bound) + " faces outside their error bound";
        else if (!certified && !(row.total_rel_error <= o.max_error && row.mean_abs_error <= o.max_error))
          problem = "error above --max-error " + std::to_string(o.max_error);
        if (!problem.empty()) {
          ++failures;
          std::fprintf(stderr, "shadow-bench compare: %s, %s %s: %s\n", bs.name.c_str(), m.name.c_str(), parameter,
                       problem.c_str());
        }
      }
      if (csv.is_open())
        csv << '"' << bs.name << "\"," << bs.kind << ',' << bs.size << ',' << row.faces << ',' << bs.light << ','
            << m.name << ',' << m.parameter_name << ',' << p << ',' << o.threads << ',' << row.prepare_s << ','
            << row.compute_s << ',' << row.total_s << ',' << row.peak_mib << ',' << row.samples << ','
            << row.lit_fraction << ',' << row.total_rel_error << ',' << row.mean_abs_error << ','
            << row.max_abs_error << '\n';
      if (json.is_open()) {
        json << (first_json ? "" : ",\n") << "  {\"scene\": \"" << json_escape(bs.name) << "\", \"kind\": \"" << bs.kind
             << "\", \"size\": " << bs.size << ", \"faces\": " << row.faces << ", \"light\": \"" << bs.light
             << "\", \"method\": \"" << m.name << "\", \"parameter_name\": \"" << m.parameter_name
             << "\", \"parameter\": " << p << ", \"threads\": " << o.threads << ", \"prepare_s\": " << row.prepare_s
             << ", \"compute_s\": " << row.compute_s << ", \"total_s\": " << row.total_s
             << ", \"peak_mib\": " << row.peak_mib << ", \"samples\": " << row.samples
             << ", \"lit_fraction\": " << row.lit_fraction << ", \"total_lit_rel_error\": " << row.total_rel_error
             << ", \"face_fraction_mean_abs_error\": " << row.mean_abs_error
             << ", \"face_fraction_max_abs_error\": " << row.max_abs_error << "}";
        first_json = false;
      }
    }
  }
  if (tty) std::fprintf(stderr, "\r\033[K");
  if (json.is_open()) json << "\n]\n";
  return failures == 0 ? 0 : 1;
}

}  // namespace bench
