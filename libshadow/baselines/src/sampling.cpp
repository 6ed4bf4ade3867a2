// SPDX-License-Identifier: GPL-3.0-or-later
#include "sampling.hpp"

#include "geometry/bounding_box.hpp"
#include "geometry/newell_normal.hpp"
#include "core/lights.hpp"
#include "runtime/parallel.hpp"
#include "geometry/unit_vector.hpp"

#include <shadow/error.hpp>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace shadow {

const FaceLighting* BaselineResult::find(std::size_t face_id, std::size_t light_id) const {
  return find_lighting(lighting, face_id, light_id);
}

namespace baselines_detail {

glm::dvec3 scene_centre(const Scene& scene) {
  const geometry::BoundingBox box =
      geometry::faces_bounding_box(scene.faces, [](const Face& f) { return f.degenerate; });
  return box.any ? box.centre() : glm::dvec3(0.0);
}

FaceFrame face_frame(const std::vector<glm::dvec3>& vertices, const glm::dvec3& shift) {
  FaceFrame fr;
  if (vertices.size() < 3) return fr;
  // Newell's normal relative to the first vertex (small numbers, accurate).
  const glm::dvec3 o = vertices[0];
  const glm::dvec3 n = geometry::newell_normal(vertices, o);
  const double len = glm::length(n);
  if (!(len > 0) || !std::isfinite(len)) return fr;
  fr.n = n / len;
  fr.area = 0.5 * len;
  // u along the longest edge (well conditioned even for slivers), made orthogonal to n.
  glm::dvec3 best(0.0);
  for (std::size_t a = 0; a < vertices.size(); ++a) {
    const glm::dvec3 e = vertices[(a + 1) % vertices.size()] - vertices[a];
    if (glm::dot(e, e) > glm::dot(best, best)) best = e;
  }
  glm::dvec3 u = best - glm::dot(best, fr.n) * fr.n;
  if (!(glm::length(u) > 0)) return fr;
  fr.u = glm::normalize(u);
  fr.v = glm::cross(fr.n, fr.u);
  fr.origin = o - shift;
  fr.polygon.reserve(vertices.size());
  for (const glm::dvec3& p : vertices) {
    const glm::dvec3 d = p - o;
    fr.polygon.emplace_back(glm::dot(d, fr.u), glm::dot(d, fr.v));
  }
  fr.ok = true;
  return fr;
}

namespace {
double cross2(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c) {
  return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}
}  // namespace

std::vector<std::array<std::uint32_t, 3>> triangulate(const std::vector<glm::dvec2>& polygon) {
  std::vector<std::array<std::uint32_t, 3>> out;
  const std::size_t n = polygon.size();
  if (n < 3) return out;
  double area2 = 0;
  for (std::size_t a = 0; a < n; ++a) {
    const glm::dvec2& p = polygon[a];
    const glm::dvec2& q = polygon[(a + 1) % n];
    area2 += p.x * q.y - q.x * p.y;
  }
  const double orient = area2 >= 0 ? 1.0 : -1.0;
  std::vector<std::uint32_t> idx(n);
  for (std::size_t a = 0; a < n; ++a) idx[a] = static_cast<std::uint32_t>(a);
  auto fan = [&] {
    for (std::size_t k = 1; k + 1 < idx.size(); ++k) out.push_back({idx[0], idx[k], idx[k + 1]});
  };
  std::size_t guard = 0;
  while (idx.size() > 3) {
    bool clipped = false;
    const std::size_t m = idx.size();
    for (std::size_t k = 0; k < m; ++k) {
      const std::uint32_t a = idx[(k + m - 1) % m], b = idx[k], c = idx[(k + 1) % m];
      if (orient * cross2(polygon[a], polygon[b], polygon[c]) <= 0) continue;  // reflex or flat
      bool empty = true;
      for (std::uint32_t r : idx) {
        if (r == a || r == b || r == c) continue;
        const glm::dvec2& p = polygon[r];
        if (orient * cross2(polygon[a], polygon[b], p) >= 0 && orient * cross2(polygon[b], polygon[c], p) >= 0 &&
            orient * cross2(polygon[c], polygon[a], p) >= 0) {
          empty = false;
          break;
        }
      }
      if (!empty) continue;
      out.push_back({a, b, c});
      idx.erase(idx.begin() + static_cast<std::ptrdiff_t>(k));
      clipped = true;
      break;
    }
    if (!clipped || ++guard > 4 * n) {  // collinear runs or self-touching: finish with a fan
      fan();
      return out;
    }
  }
  out.push_back({idx[0], idx[1], idx[2]});
  return out;
}

ShiftedLight shifted_light(const Scene& scene, std::size_t light_id, const glm::dvec3& shift) {
  // Checked as the engine checks it; an extended light stands for its centre (an area light's
  // centroid, a disk's centre, a sun disk's central direction), as FaceLighting::lit_area of
  // the exact engine does (docs/area-lights.md).
  detail::check_light(scene.lights[light_id], scene.source.string(), "lights[" + std::to_string(light_id) + "]");
  const Light l = detail::centre_light(scene.lights[light_id]);
  ShiftedLight out;
  if (l.type == LightType::Point) {
    out.point = true;
    out.position = l.position - shift;
    return out;
  }
  out.to_light = geometry::unit(l.to_light);  // scaled first: tiny or huge vectors normalise too
  return out;
}

std::vector<std::size_t> selected_lights(const Scene& scene, const std::vector<std::size_t>& wanted) {
  std::vector<std::size_t> out;
  if (wanted.empty()) {
    for (std::size_t l = 0; l < scene.lights.size(); ++l) out.push_back(l);
    return out;
  }
  for (std::size_t l : wanted) {
    if (l >= scene.lights.size())
      throw InputError({scene.source.string(), "options.lights"}, "light " + std::to_string(l) + " does not exist");
    out.push_back(l);
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

unsigned thread_count(unsigned requested) { return runtime::resolve_threads(requested); }

bool faces_light(const FaceFrame& frame, const ShiftedLight& light) {
  if (!frame.ok) return false;
  if (light.point) return glm::dot(frame.n, light.position - frame.origin) > 0;
  return glm::dot(frame.n, light.to_light) > 0;
}

namespace {

/// The cell-centred grid of a face: nu x nv cells of side h from (u0, v0) (the first centre).
struct Grid {
  double h = 1, u0 = 0, v0 = 0;
  std::int64_t nu = 1, nv = 1;
};

Grid make_grid(const FaceFrame& fr, double h, std::uint64_t cap) {
  glm::dvec2 lo(std::numeric_limits<double>::max()), hi(std::numeric_limits<double>::lowest());
  for (const glm::dvec2& p : fr.polygon) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  const double w = hi.x - lo.x, d = hi.y - lo.y;
  Grid g;
  auto cells = [](double len, double step) {
    return static_cast<std::int64_t>(std::max(1.0, std::ceil(len / step - 1e-9)));
  };
  g.h = h;
  g.nu = cells(w, h);
  g.nv = cells(d, h);
  const double count = static_cast<double>(g.nu) * static_cast<double>(g.nv);
  if (count > static_cast<double>(cap)) {  // widen to respect the cap
    g.h = h * std::sqrt(count / static_cast<double>(cap)) * 1.0001;
    g.nu = cells(w, g.h);
    g.nv = cells(d, g.h);
  }
  // Centred on the bounding rectangle (the pattern does not depend on which vertex comes first),
  // then moved by irrational fractions of a cell: a grid in step with the scene's own
  // coordinates (centimetres) puts whole rows of samples exactly on shadow edges, where a ray
  // grazing an edge counts as blocked, and biases the lit area by about h times the edge length.
  g.u0 = lo.x + 0.5 * (w - static_cast<double>(g.nu) * g.h) + (0.5 + 0.1035533906) * g.h;
  g.v0 = lo.y + 0.5 * (d - static_cast<double>(g.nv) * g.h) + (0.5 + 0.1830127019) * g.h;
  return g;
}

/// Column range [first, last) of grid centres inside the polygon on row `v`, interval by interval.
template <class F>
void row_intervals(const FaceFrame& fr, const Grid& g, double v, std::vector<double>& xs, F&& each_interval) {
  xs.clear();
  const std::size_t n = fr.polygon.size();
  for (std::size_t a = 0, b = n - 1; a < n; b = a++) {
    const glm::dvec2& p = fr.polygon[a];
    const glm::dvec2& q = fr.polygon[b];
    if ((p.y > v) != (q.y > v)) xs.push_back(p.x + (v - p.y) * (q.x - p.x) / (q.y - p.y));
  }
  std::sort(xs.begin(), xs.end());
  for (std::size_t k = 0; k + 1 < xs.size(); k += 2) {
    // centres u0 + c h with xs[k] < u < xs[k+1]
    const auto first = static_cast<std::int64_t>(std::max(0.0, std::floor((xs[k] - g.u0) / g.h) + 1));
    const auto last = static_cast<std::int64_t>(
        std::min(static_cast<double>(g.nu), std::ceil((xs[k + 1] - g.u0) / g.h)));
    if (last > first) each_interval(first, last);
  }
}

struct Task {
  std::size_t job = 0;
  std::int64_t row_begin = 0, row_end = 0;  // row_begin < 0: the single fallback sample
};

}  // namespace

void run_sampling(const std::vector<SampleJob>& jobs, unsigned threads, std::uint64_t max_samples_per_face,
                  const std::function<BatchTest(unsigned)>& make_test, std::vector<std::uint64_t>& samples,
                  std::vector<std::uint64_t>& lit) {
  std::vector<Grid> grids(jobs.size());
  std::vector<Task> tasks;
  std::vector<double> xs;
  constexpr std::int64_t block = 1 << 15;  // samples per work item, about
  for (std::size_t j = 0; j < jobs.size(); ++j) {
    const FaceFrame& fr = *jobs[j].frame;
    grids[j] = make_grid(fr, jobs[j].spacing, std::max<std::uint64_t>(1, max_samples_per_face));
    const Grid& g = grids[j];
    // Count first: a face smaller than a cell gets one sample instead of none.
    std::int64_t count = 0;
    for (std::int64_t r = 0; r < g.nv && count == 0; ++r)
      row_intervals(fr, g, g.v0 + static_cast<double>(r) * g.h, xs,
                    [&](std::int64_t a, std::int64_t b) { count += b - a; });
    if (count == 0) {
      tasks.push_back({j, -1, -1});
      continue;
    }
    const std::int64_t rows_per_task = std::max<std::int64_t>(1, block / std::max<std::int64_t>(1, g.nu));
    for (std::int64_t r = 0; r < g.nv; r += rows_per_task) tasks.push_back({j, r, std::min(g.nv, r + rows_per_task)});
  }
  std::vector<std::atomic<std::uint64_t>> s(samples.size()), l(samples.size());
  for (std::size_t k = 0; k < samples.size(); ++k) {
    s[k] = 0;
    l[k] = 0;
  }
  // The one scheduler (runtime/parallel.hpp): tasks handed out dynamically; per worker a test and
  // a row buffer, made before the run so that no item allocates them.
  const unsigned workers = std::max(1u, std::min<unsigned>(threads, static_cast<unsigned>(std::max<std::size_t>(tasks.size(), 1))));
  std::vector<BatchTest> tests;
  for (unsigned t = 0; t < workers; ++t) tests.push_back(make_test(t));
  std::vector<std::vector<double>> row_buffers(workers);
  runtime::parallel_for(tasks.size(), workers, [&](unsigned t, std::size_t k) {
    const BatchTest& test = tests[t];
    std::vector<double>& row_xs = row_buffers[t];
    glm::dvec3 batch[kBatch];
    std::size_t filled = 0;
    const Task& task = tasks[k];
    const SampleJob& job = jobs[task.job];
    const FaceFrame& fr = *job.frame;
    const Grid& g = grids[task.job];
    std::uint64_t ns = 0, nl = 0;
    if (task.row_begin < 0) {
      // Centre of the bounding rectangle, else the vertex average, else the first vertex.
      glm::dvec2 c(g.u0 + 0.5 * static_cast<double>(g.nu - 1) * g.h, g.v0 + 0.5 * static_cast<double>(g.nv - 1) * g.h);
      glm::dvec3 p = fr.origin + c.x * fr.u + c.y * fr.v;
      ns = 1;
      nl = test(&p, 1, job);
    } else {
      for (std::int64_t r = task.row_begin; r < task.row_end; ++r) {
        const double v = g.v0 + static_cast<double>(r) * g.h;
        const glm::dvec3 row_origin = fr.origin + v * fr.v;
        row_intervals(fr, g, v, row_xs, [&](std::int64_t a, std::int64_t b) {
          for (std::int64_t c = a; c < b; ++c) {
            const glm::dvec3 p = row_origin + (g.u0 + static_cast<double>(c) * g.h) * fr.u;
            ++ns;
            batch[filled++] = p;
            if (filled == kBatch) {
              nl += test(batch, filled, job);
              filled = 0;
            }
          }
        });
      }
      if (filled > 0) nl += test(batch, filled, job);
    }
    s[job.pair] += ns;
    l[job.pair] += nl;
  });
  for (std::size_t k = 0; k < samples.size(); ++k) {
    samples[k] = s[k];
    lit[k] = l[k];
  }
}

std::vector<glm::dvec3> grid_points(const FaceFrame& fr, double spacing, std::uint64_t cap) {
  std::vector<glm::dvec3> out;
  if (!fr.ok) return out;
  const Grid g = make_grid(fr, spacing, std::max<std::uint64_t>(1, cap));
  std::vector<double> xs;
  for (std::int64_t r = 0; r < g.nv; ++r) {
    const double v = g.v0 + static_cast<double>(r) * g.h;
    const glm::dvec3 row_origin = fr.origin + v * fr.v;
    row_intervals(fr, g, v, xs, [&](std::int64_t a, std::int64_t b) {
      for (std::int64_t c = a; c < b; ++c) out.push_back(row_origin + (g.u0 + static_cast<double>(c) * g.h) * fr.u);
    });
  }
  if (out.empty()) {
    const glm::dvec2 c(g.u0 + 0.5 * static_cast<double>(g.nu - 1) * g.h, g.v0 + 0.5 * static_cast<double>(g.nv - 1) * g.h);
    out.push_back(fr.origin + c.x * fr.u + c.y * fr.v);
  }
  return out;
}

Setup make_setup(const Scene& scene, const std::vector<std::size_t>& wanted_lights, bool recentre) {
  Setup s;
  s.shift = recentre ? scene_centre(scene) : glm::dvec3(0.0);
  s.lights = selected_lights(scene, wanted_lights);
  for (std::size_t l : s.lights) s.shifted.push_back(shifted_light(scene, l, s.shift));
  s.frames.resize(scene.faces.size());
  for (std::size_t f = 0; f < scene.faces.size(); ++f)
    if (!scene.faces[f].degenerate) s.frames[f] = face_frame(scene.faces[f].vertices, s.shift);
  for (std::size_t f = 0; f < scene.faces.size(); ++f) {
    if (!scene.is_receiver(f)) continue;
    for (std::size_t k = 0; k < s.lights.size(); ++k) {
      FaceLighting fl;
      fl.face_id = f;
      fl.light_id = s.lights[k];
      fl.area = s.frames[f].ok ? s.frames[f].area : 0.0;
      fl.shadow_area = fl.area;
      fl.faces_light = faces_light(s.frames[f], s.shifted[k]);
      s.result.lighting.push_back(fl);
    }
  }
  return s;
}

std::vector<SampleJob> Setup::jobs(std::size_t k) const {
  std::vector<SampleJob> out;
  for (std::size_t e = 0; e < result.lighting.size(); ++e) {
    const FaceLighting& fl = result.lighting[e];
    if (fl.light_id != lights[k] || !fl.faces_light) continue;
    out.push_back({e, &frames[fl.face_id], 1.0});
  }
  return out;
}

void finish(Setup& setup, const std::vector<std::uint64_t>& samples, const std::vector<std::uint64_t>& lit) {
  for (std::size_t e = 0; e < setup.result.lighting.size(); ++e) {
    FaceLighting& fl = setup.result.lighting[e];
    setup.result.samples += samples[e];
    const double fraction = samples[e] > 0 ? static_cast<double>(lit[e]) / static_cast<double>(samples[e]) : 0.0;
    fl.lit_fraction = fl.faces_light ? fraction : 0.0;
    fl.lit_area = fl.lit_fraction * fl.area;
    fl.shadow_area = fl.area - fl.lit_area;
  }
}

namespace {
bool finite_point(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
}  // namespace

/// Shift and face frames (no lights), as the other baselines have them.
Setup frames_setup(const Scene& scene, bool recentre) {
  Setup s;
  s.shift = recentre ? scene_centre(scene) : glm::dvec3(0.0);
  s.frames.resize(scene.faces.size());
  for (std::size_t f = 0; f < scene.faces.size(); ++f)
    if (!scene.faces[f].degenerate) s.frames[f] = face_frame(scene.faces[f].vertices, s.shift);
  return s;
}

void check_points(const Scene& scene, const std::vector<SurfacePoint>& points, const char* place) {
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (points[i].face_id >= scene.faces.size())
      throw InputError({"", place}, "point " + std::to_string(i) + " names face " + std::to_string(points[i].face_id) +
                                        ", which does not exist");
    if (!finite_point(points[i].position)) throw InputError({"", place}, "point " + std::to_string(i) + " is not finite");
  }
}

}  // namespace baselines_detail
}  // namespace shadow
