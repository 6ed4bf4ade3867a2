// SPDX-License-Identifier: GPL-3.0-or-later
// Progressive refinement (shooting) radiosity on elements cut from the exact lit and shadowed
// fragments of the direct light (docs/radiosity.md).
#include <shadow/radiosity.hpp>

#include "runtime/parallel.hpp"
#include "radiosity/contacts.hpp"
#include "radiosity/shaft.hpp"
#include "radiosity/shooter_view.hpp"
#include "radiosity/triangles.hpp"
#include "radiosity/visible_part.hpp"

#include <shadow/area_lights.hpp>
#include <shadow/error.hpp>
#include <shadow/lighting.hpp>
#include <shadow/shadows.hpp>

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <functional>
#include <memory>
#include <string>

namespace shadow {
namespace {

/// An element while solving: a triangle with its receiving points.
struct Element {
  std::size_t face = 0;
  radiosity::Triangle triangle;
  double area = 0.0;
  glm::dvec3 centroid{0.0};
  double radius = 0.0;  // largest distance from the centroid to a vertex
  std::size_t fragment = SIZE_MAX;  // index into the first light's fragments, or none
  std::size_t patch = 0;            // the patch (a coarser triangle) that holds it
};

/// A patch: the triangle that shoots for the elements it holds (Cohen et al.'s substructuring:
/// shooters coarse, receivers fine).
struct Patch {
  std::size_t face = 0;
  radiosity::Triangle triangle;
  double area = 0.0;
  glm::dvec3 centroid{0.0};
  double radius = 0.0;
  std::size_t first = 0, count = 0;  // its elements
};

void check_options(const RadiosityOptions& o) {
  if (!(o.max_element_area >= 0.0) || !std::isfinite(o.max_element_area))
    throw InputError({"", "max_element_area"}, "max_element_area must be a finite number >= 0 (m^2)");
  if (!(o.patch_area >= 0.0) || !std::isfinite(o.patch_area))
    throw InputError({"", "patch_area"}, "patch_area must be a finite number >= 0 (m^2)");
  if (!(o.tolerance > 0.0) || !(o.tolerance < 1.0))
    throw InputError({"", "tolerance"}, "tolerance must be in (0, 1): the unshot fraction to stop at");
  runtime::checked_threads(o.threads);
}

void add_element(std::vector<Element>& out, std::size_t face, const radiosity::Triangle& t, std::size_t fragment,
                 std::size_t patch) {
  Element e;
  e.patch = patch;
  e.face = face;
  e.triangle = t;
  e.area = radiosity::triangle_area(t);
  e.centroid = (t[0] + t[1] + t[2]) / 3.0;
  for (const glm::dvec3& v : t) e.radius = std::max(e.radius, glm::length(v - e.centroid));
  e.fragment = fragment;
  if (e.area > 0.0) out.push_back(e);
}

/// The patches and their elements: each face's fragments under the first light (its whole
/// polygon where it has none), triangulated, refined to patch_area (the patches), each refined
/// to max_area (its elements, consecutive).
void make_elements(const Scene& scene, const std::vector<Fragment>& fragments, double max_area, double patch_area,
                   std::vector<Patch>& patches, std::vector<Element>& elements) {
  std::vector<std::vector<std::size_t>> by_face(scene.faces.size());
  for (std::size_t i = 0; i < fragments.size(); ++i)
    if (fragments[i].light_id == 0 && fragments[i].face_id < scene.faces.size()) by_face[fragments[i].face_id].push_back(i);
  // Cut along where other faces meet each face: a floor element under a box's wall would
  // average the lit floor with the closed-off part beneath the box.
  const std::vector<std::vector<radiosity::Segment>> contacts = radiosity::contact_segments(scene);
  std::vector<radiosity::Triangle> coarse, fine, cut;
  for (std::size_t f = 0; f < scene.faces.size(); ++f) {
    const Face& face = scene.faces[f];
    if (face.degenerate || face.vertices.size() < 3) continue;
    const glm::dvec3 n = radiosity::newell_normal(face.vertices);
    auto add_polygon = [&](const std::vector<glm::dvec3>& polygon, std::size_t fragment) {
      cut.clear();
      for (const radiosity::Triangle& t : radiosity::triangulate(polygon))
        radiosity::cut_along(t, glm::normalize(n), contacts[f], cut);
      for (const radiosity::Triangle& t : cut) {
        coarse.clear();
        radiosity::refine(t, patch_area, coarse);
        for (const radiosity::Triangle& c : coarse) {
          Patch p;
          p.face = f;
          p.triangle = c;
          p.area = radiosity::triangle_area(c);
          p.centroid = (c[0] + c[1] + c[2]) / 3.0;
          for (const glm::dvec3& v : c) p.radius = std::max(p.radius, glm::length(v - p.centroid));
          p.first = elements.size();
          fine.clear();
          radiosity::refine(c, max_area, fine);
          for (const radiosity::Triangle& e : fine) add_element(elements, f, e, fragment, patches.size());
          p.count = elements.size() - p.first;
          if (p.count > 0) patches.push_back(p);
        }
      }
    };
    if (by_face[f].empty()) add_polygon(face.vertices, SIZE_MAX);
    for (std::size_t i : by_face[f]) add_polygon(fragments[i].polygon, i);
  }
}

/// Whether `p` (on the plane of `polygon`) lies inside it (even-odd rule in the dominant chart).
bool inside(const std::vector<glm::dvec3>& polygon, const glm::dvec3& p) {
  const glm::dvec3 n = radiosity::newell_normal(polygon);
  int k = 0;
  for (int a = 1; a < 3; ++a)
    if (std::abs(n[a]) > std::abs(n[k])) k = a;
  const int i = (k + 1) % 3, j = (k + 2) % 3;
  bool in = false;
  for (std::size_t a = 0, b = polygon.size() - 1; a < polygon.size(); b = a++) {
    const glm::dvec3 &u = polygon[a], &v = polygon[b];
    if ((u[j] > p[j]) != (v[j] > p[j]) && p[i] < (v[i] - u[i]) * (p[j] - u[j]) / (v[j] - u[j]) + u[i]) in = !in;
  }
  return in;
}

/// Each element's direct irradiance from the scene's lights, with exact shadows: the fragment's
/// lit flag for the first light, a lit fragment of the same face holding the centroid for the
/// others (hard lights), light_irradiance at the centroid for extended lights.
std::vector<double> direct_irradiance(const Scene& scene, const std::vector<Fragment>& fragments,
                                      const std::vector<Element>& elements, const std::vector<glm::dvec3>& normals,
                                      unsigned threads) {
  std::vector<double> direct(elements.size(), 0.0);
  // An extended light's irradiance varies across a penumbra cell: the mean of the three interior
  // points of the degree-2 triangle rule, each exact.
  std::vector<SurfacePoint> points;
  for (const Element& e : elements)
    for (int c = 0; c < 3; ++c)
      points.push_back({e.face, (4.0 * e.triangle[c] + e.triangle[(c + 1) % 3] + e.triangle[(c + 2) % 3]) / 6.0});
  for (std::size_t l = 0; l < scene.lights.size(); ++l) {
    const Light& light = scene.lights[l];
    if (light.is_extended()) {
      const std::vector<double> h = light_irradiance(scene, light, points, threads);
      for (std::size_t i = 0; i < elements.size(); ++i) direct[i] += (h[3 * i] + h[3 * i + 1] + h[3 * i + 2]) / 3.0;
      continue;
    }
    std::vector<std::vector<std::size_t>> lit(scene.faces.size());
    if (l > 0)
      for (std::size_t i = 0; i < fragments.size(); ++i)
        if (fragments[i].light_id == l && fragments[i].lit) lit[fragments[i].face_id].push_back(i);
    for (std::size_t i = 0; i < elements.size(); ++i) {
      const Element& e = elements[i];
      bool is_lit = false;
      if (l == 0) {
        is_lit = e.fragment != SIZE_MAX && fragments[e.fragment].lit;
      } else {
        for (std::size_t k : lit[e.face]) is_lit = is_lit || inside(fragments[k].polygon, e.centroid);
      }
      if (is_lit) direct[i] += irradiance(light, e.centroid, normals[e.face]);
    }
  }
  return direct;
}

/// The receiving rule of an element at distance `gap` from a shooter (R: the sum of their
/// circumradii): beyond 6 R the centroid; within, the 3-point rule (degree 2); within 2 R, where
/// the point form factor varies fast (logarithmically along a shared edge), a 4 x 4 collapsed
/// Gauss rule. Returns the estimate and sets `change` to its difference from the rule below.
template <class PointFactor>
double integrate_over_element(const Element& e, double gap, double reach, const PointFactor& at, double& change) {
  static const std::pair<std::vector<double>, std::vector<double>> gauss = [] {
    std::pair<std::vector<double>, std::vector<double>> g;
    radiosity::gauss_legendre01(4, g.first, g.second);
    return g;
  }();
  change = 0.0;
  double f = at(e.centroid);
  if (gap < 6.0 * reach) {
    double f3 = 0.0;
    for (int c = 0; c < 3; ++c)
      f3 += at((4.0 * e.triangle[c] + e.triangle[(c + 1) % 3] + e.triangle[(c + 2) % 3]) / 6.0) / 3.0;
    change = std::abs(f3 - f);
    f = f3;
  }
  if (gap < 2.0 * reach) {
    const radiosity::Triangle& t = e.triangle;
    double f16 = 0.0;
    for (std::size_t a = 0; a < gauss.first.size(); ++a)
      for (std::size_t b = 0; b < gauss.first.size(); ++b) {
        const double u = gauss.first[a], v = gauss.first[b];
        f16 += 2.0 * u * gauss.second[a] * gauss.second[b] * at(t[0] + u * (t[1] - t[0]) + u * v * (t[2] - t[1]));
      }
    change = std::abs(f16 - f);
    f = f16;
  }
  return f;
}

/// Where the form factors come from: visibility in doubles through shaft culling (the default),
/// or the exact machinery point by point (RadiosityOptions::exact_visibility, for checking).
class Receivers {
 public:
  Receivers(const Scene& scene, unsigned threads, bool exact)
      : exact_(exact), culler_(scene), workers_(std::max(1u, threads)) {
    if (exact) view_ = std::make_unique<radiosity::ShooterView>(scene, threads);
    normals_.assign(scene.faces.size(), glm::dvec3(0.0));
    for (std::size_t f = 0; f < scene.faces.size(); ++f) {
      const glm::dvec3 n = radiosity::newell_normal(scene.faces[f].vertices);
      if (!scene.faces[f].degenerate && glm::length(n) > 0.0) normals_[f] = glm::normalize(n);
    }
  }

  std::size_t exact_evaluations() const { return view_ ? view_->exact_evaluations() : 0; }
  const std::vector<glm::dvec3>& normals() const { return normals_; }

  /// The form factor from each element to patch `s` and the quadrature change that estimates
  /// its error. Elements on the patch's face get 0 (a plane does not see itself).
  void receive(const std::vector<Patch>& patches, const std::vector<Element>& elements, const Patch& s,
               unsigned threads, std::vector<double>& factor, std::vector<double>& quad) {
    const std::vector<glm::dvec3> source = {s.triangle[0], s.triangle[1], s.triangle[2]};
    factor.assign(elements.size(), 0.0);
    quad.assign(elements.size(), 0.0);
    if (exact_) {
      std::vector<std::vector<glm::dvec3>> pieces;
      if (s.count > 1)
        for (std::size_t i = s.first; i < s.first + s.count; ++i)
          pieces.push_back({elements[i].triangle[0], elements[i].triangle[1], elements[i].triangle[2]});
      view_->set_shooter(s.face, source, std::move(pieces));
    }
    if (exact_) {
      runtime::parallel_for(elements.size(), threads, [&](unsigned worker, std::size_t i) {
        const Element& e = elements[i];
        if (e.face == s.face || !faces_each_other(e.triangle, e.face, s.triangle, s.face)) return;
        const double gap = glm::length(e.centroid - s.centroid), reach = e.radius + s.radius;
        factor[i] = integrate_over_element(e, gap, reach, [&](const glm::dvec3& p) {
          return view_->evaluate(worker, {e.face, p});
        }, quad[i]);
      });
      return;
    }
    // One shaft per receiving patch serves all its elements (each element's shaft lies inside it).
    const radiosity::SourceChart chart(source);
    runtime::parallel_for(patches.size(), threads, [&](unsigned worker, std::size_t r) {
      const Patch& receiver = patches[r];
      if (receiver.face == s.face || !faces_each_other(receiver.triangle, receiver.face, s.triangle, s.face)) return;
      Worker& w = workers_[worker];
      if (culler_.candidates({receiver.triangle[0], receiver.triangle[1], receiver.triangle[2]}, receiver.face, source,
                             s.face, w.shaft, w.faces))
        return;  // one face hides the shooter from all of the receiving patch
      w.occluders.clear();
      for (std::size_t f : w.faces) w.occluders.push_back(&culler_.vertices(f));
      const glm::dvec3& nr = normals_[receiver.face];
      for (std::size_t i = receiver.first; i < receiver.first + receiver.count; ++i) {
        const Element& e = elements[i];
        if (!faces_each_other(e.triangle, e.face, s.triangle, s.face)) continue;
        const double gap = glm::length(e.centroid - s.centroid), reach = e.radius + s.radius;
        factor[i] = integrate_over_element(e, gap, reach, [&](const glm::dvec3& p) {
          return w.occluders.empty() ? chart.unoccluded(p, nr, w.visible)
                                     : chart.form_factor(p, nr, w.occluders, w.visible);
        }, quad[i]);
      }
    });
  }

 private:
  struct Worker {
    radiosity::VisibleScratch visible;
    radiosity::ShaftCuller::Scratch shaft;
    std::vector<std::size_t> faces;
    std::vector<const std::vector<glm::dvec3>*> occluders;
  };

  /// Some of the receiver in front of the shooter and some of the shooter in front of the receiver.
  bool faces_each_other(const radiosity::Triangle& r, std::size_t r_face, const radiosity::Triangle& s,
                        std::size_t s_face) const {
    const glm::dvec3 &nr = normals_[r_face], &ns = normals_[s_face];
    bool a = false, b = false;
    for (const glm::dvec3& v : r) a = a || glm::dot(ns, v - s[0]) > 0.0;
    for (const glm::dvec3& v : s) b = b || glm::dot(nr, v - r[0]) > 0.0;
    return a && b;
  }

  bool exact_;
  radiosity::ShaftCuller culler_;
  std::unique_ptr<radiosity::ShooterView> view_;
  std::vector<glm::dvec3> normals_;
  std::vector<Worker> workers_;
};

/// Power totals of a solution (W).
struct Totals {
  double absorbed = 0.0, emitted = 0.0, direct = 0.0;
};

/// The result's elements and per-face means from the solver's arrays; returns the totals.
Totals fill_arrays(const Scene& scene, const std::vector<Element>& elements, const std::vector<double>& direct,
                   const std::vector<double>& rho, const std::vector<double>& emit, const std::vector<double>& b,
                   const std::vector<double>& h, RadiosityResult& result) {
  const std::size_t n = elements.size();
  result.elements.resize(n);
  result.faces.resize(scene.faces.size());
  for (std::size_t f = 0; f < scene.faces.size(); ++f) result.faces[f].face_id = f;
  Totals t;
  for (std::size_t i = 0; i < n; ++i) {
    const Element& e = elements[i];
    RadiosityElement& out = result.elements[i];
    out.face_id = e.face;
    out.polygon = {e.triangle[0], e.triangle[1], e.triangle[2]};
    out.area = e.area;
    out.radiosity = b[i];
    out.irradiance = h[i];
    out.direct_irradiance = direct[i];
    out.reflectance = rho[i];
    out.emittance = emit[i];
    FaceRadiosity& face = result.faces[e.face];
    face.area += e.area;
    face.radiosity += b[i] * e.area;
    face.irradiance += h[i] * e.area;
    face.direct_irradiance += direct[i] * e.area;
    ++face.elements;
    t.absorbed += (1.0 - rho[i]) * h[i] * e.area;
    t.emitted += emit[i] * e.area;
    t.direct += direct[i] * e.area;
  }
  for (FaceRadiosity& face : result.faces)
    if (face.area > 0) {
      face.radiosity /= face.area;
      face.irradiance /= face.area;
      face.direct_irradiance /= face.area;
    }
  return t;
}

/// One channel's shooting state: what is left of the light to shoot, and the totals so far.
struct Channel {
  std::vector<double> rho, b, h, unshot;
  double power_in = 0.0, unshot_power = 0.0, escaped = 0.0, quadrature = 0.0, shot_total = 0.0;
  std::size_t shots = 0;
};

/// The form factors of each patch to every element, computed when the patch first shoots and
/// kept within a memory budget: a patch shoots many times (every time its elements have gathered
/// enough again), and the colour channels shoot the same patches.
class FactorCache {
 public:
  FactorCache(Receivers& receivers, const std::vector<Patch>& patches, const std::vector<Element>& elements,
              unsigned threads)
      : receivers_(receivers), patches_(patches), elements_(elements), threads_(threads),
        factor_(patches.size()), quad_(patches.size()) {}

  /// Patch k's row: the form factor from each element to it and its quadrature change.
  void row(std::size_t k, std::vector<double>& factor, std::vector<double>& quad) {
    if (!factor_[k].empty()) {
      factor = factor_[k];
      quad.assign(quad_[k].begin(), quad_[k].end());
      return;
    }
    receivers_.receive(patches_, elements_, patches_[k], threads_, factor, quad);
    const std::size_t bytes = elements_.size() * (sizeof(double) + sizeof(float));
    if (bytes_ + bytes <= kBudget) {
      factor_[k] = factor;
      quad_[k].assign(quad.begin(), quad.end());
      bytes_ += bytes;
    }
  }

 private:
  static constexpr std::size_t kBudget = std::size_t(512) << 20;
  Receivers& receivers_;
  const std::vector<Patch>& patches_;
  const std::vector<Element>& elements_;
  unsigned threads_;
  std::vector<std::vector<double>> factor_;
  std::vector<std::vector<float>> quad_;
  std::size_t bytes_ = 0;
};

/// A channel whose elements reflect `rho` and start from their emittance and direct light.
Channel start_channel(const std::vector<Element>& elements, const std::vector<double>& rho,
                      const std::vector<double>& emit, const std::vector<double>& direct) {
  Channel c;
  const std::size_t n = elements.size();
  c.rho = rho;
  c.b.resize(n);
  c.unshot.resize(n);
  c.h = direct;
  for (std::size_t i = 0; i < n; ++i) {
    c.b[i] = c.unshot[i] = emit[i] + rho[i] * direct[i];
    c.power_in += c.unshot[i] * elements[i].area;
  }
  c.unshot_power = c.power_in;
  return c;
}

/// Shoots until the unshot power is at most the tolerance of the power put in: the patch with
/// the most unshot power sends its elements' mean unshot radiosity to every element.
void shoot(Channel& c, const std::vector<Patch>& patches, const std::vector<Element>& elements, FactorCache& cache,
           const RadiosityOptions& options, const std::function<void(const Channel&, bool)>& report) {
  const std::size_t n = elements.size();
  std::vector<double> factor, quad;
  while (c.power_in > 0.0 && c.unshot_power > options.tolerance * c.power_in &&
         (options.max_shots == 0 || c.shots < options.max_shots)) {
    std::size_t k = 0;
    double best = -1.0;
    for (std::size_t p = 0; p < patches.size(); ++p) {
      double power = 0.0;
      for (std::size_t i = patches[p].first; i < patches[p].first + patches[p].count; ++i)
        power += c.unshot[i] * elements[i].area;
      if (power > best) best = power, k = p;
    }
    if (!(best > 0.0)) break;
    const Patch& s = patches[k];
    const double db = best / s.area;
    cache.row(k, factor, quad);
    for (std::size_t i = s.first; i < s.first + s.count; ++i) c.unshot[i] = 0.0;
    double got = 0.0, diff = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      const double received = db * factor[i];
      if (received == 0.0) continue;
      c.h[i] += received;
      c.b[i] += c.rho[i] * received;
      c.unshot[i] += c.rho[i] * received;
      got += received * elements[i].area;
      diff += db * quad[i] * elements[i].area;
    }
    c.shot_total += best;
    c.escaped += best - got;
    c.quadrature += diff;
    ++c.shots;
    c.unshot_power = 0.0;
    for (std::size_t i = 0; i < n; ++i) c.unshot_power += c.unshot[i] * elements[i].area;
    if (report) report(c, false);
  }
  if (report) report(c, true);
}

/// Channel k (0, 1, 2: red, green, blue) of a material's reflectance: its RGB value where one
/// was given, its scalar reflectance otherwise.
double channel_reflectance(const Material& m, int k) {
  return m.reflectance_rgb == glm::dvec3(0.0) ? m.reflectance : m.reflectance_rgb[k];
}

}  // namespace

RadiosityResult solve_radiosity(const Scene& scene, const RadiosityOptions& options) {
  check_options(options);
  if (!options.face_irradiance.empty()) {
    if (options.face_irradiance.size() != scene.faces.size())
      throw InputError({"", "face_irradiance"}, "face_irradiance has " + std::to_string(options.face_irradiance.size()) +
                                                    " values for " + std::to_string(scene.faces.size()) + " faces");
    for (std::size_t f = 0; f < scene.faces.size(); ++f)
      if (!(options.face_irradiance[f] >= 0.0) || !std::isfinite(options.face_irradiance[f]))
        throw InputError({"", "face_irradiance"}, "face_irradiance of face " + std::to_string(f) +
                                                      " must be a finite number >= 0");
  }
  if (!options.face_reflectance.empty()) {
    if (options.face_reflectance.size() != scene.faces.size())
      throw InputError({"", "face_reflectance"}, "face_reflectance has " + std::to_string(options.face_reflectance.size()) +
                                                     " values for " + std::to_string(scene.faces.size()) + " faces");
    for (std::size_t f = 0; f < scene.faces.size(); ++f)
      if (!(options.face_reflectance[f] >= 0.0 && options.face_reflectance[f] < 1.0))
        throw InputError({"", "face_reflectance"}, "face_reflectance of face " + std::to_string(f) + " must be in [0, 1)");
  }
  const unsigned threads = runtime::resolve_threads(options.threads);
  std::vector<Fragment> fragments;
  if (!scene.lights.empty() && options.face_irradiance.empty()) {
    ShadowOptions so;
    so.threads = options.threads;
    so.planes = false;
    so.polygons = true;
    fragments = compute_shadows(scene, so).fragments;
  }
  std::vector<Patch> patches;
  std::vector<Element> elements;
  const double patch_area = options.patch_area > 0 ? options.patch_area : 16.0 * options.max_element_area;
  make_elements(scene, fragments, options.max_element_area, patch_area, patches, elements);
  const std::size_t n = elements.size();
  Receivers receivers(scene, threads, options.exact_visibility);
  std::vector<double> direct;
  if (options.face_irradiance.empty()) {
    direct = direct_irradiance(scene, fragments, elements, receivers.normals(), options.threads);
  } else {
    direct.resize(n);
    for (std::size_t i = 0; i < n; ++i) direct[i] = options.face_irradiance[elements[i].face];
  }

  std::vector<double> rho(n), emit(n);
  double reflectance_area = 0.0, area = 0.0;
  bool colour = false;
  for (std::size_t i = 0; i < n; ++i) {
    const Material& m = scene.material_of(elements[i].face);
    const bool given = !options.face_reflectance.empty();
    rho[i] = given ? options.face_reflectance[elements[i].face] : m.reflectance;
    emit[i] = m.emittance;
    reflectance_area += rho[i] * elements[i].area;
    area += elements[i].area;
    for (int k = 0; k < 3 && !given; ++k) colour = colour || channel_reflectance(m, k) != m.reflectance;
  }
  RadiosityResult result;
  auto last = std::chrono::steady_clock::now();
  const auto report = [&](const Channel& c, bool force) {
    if (!options.progress) return;
    const auto now = std::chrono::steady_clock::now();
    if (!force && now - last < std::chrono::milliseconds(500)) return;
    last = now;
    options.progress({c.shots, c.power_in > 0 ? c.unshot_power / c.power_in : 0.0});
  };
  FactorCache cache(receivers, patches, elements, threads);
  Channel mean = start_channel(elements, rho, emit, direct);
  shoot(mean, patches, elements, cache, options, report);
  // Colour: the same shooting per channel with that channel's reflectance; the form factors
  // come from the cache.
  std::array<Channel, 3> rgb;
  if (colour)
    for (int k = 0; k < 3; ++k) {
      std::vector<double> rho_k(n);
      for (std::size_t i = 0; i < n; ++i) rho_k[i] = channel_reflectance(scene.material_of(elements[i].face), k);
      rgb[static_cast<std::size_t>(k)] = start_channel(elements, rho_k, emit, direct);
      shoot(rgb[static_cast<std::size_t>(k)], patches, elements, cache, options, {});
    }

  result.shots = mean.shots;
  const Totals totals = fill_arrays(scene, elements, direct, rho, emit, mean.b, mean.h, result);
  for (std::size_t i = 0; i < n; ++i) {
    RadiosityElement& e = result.elements[i];
    for (int k = 0; k < 3; ++k) {
      const std::size_t c = static_cast<std::size_t>(k);
      e.radiosity_rgb[k] = colour ? rgb[c].b[i] : mean.b[i];
      e.irradiance_rgb[k] = colour ? rgb[c].h[i] : mean.h[i];
    }
    FaceRadiosity& face = result.faces[e.face_id];
    face.radiosity_rgb += e.radiosity_rgb * (e.area / face.area);
    face.irradiance_rgb += e.irradiance_rgb * (e.area / face.area);
  }
  result.colour = colour;
  if (colour) {
    for (const Channel& c : rgb) result.channel_unshot_fraction = std::max(result.channel_unshot_fraction,
                                                                            c.power_in > 0 ? c.unshot_power / c.power_in : 0.0);
  }
  const double absorbed = totals.absorbed, emitted = totals.emitted, direct_power = totals.direct;
  result.patches = patches.size();
  result.exact_evaluations = receivers.exact_evaluations();
  result.emitted_power = emitted;
  result.direct_power = direct_power;
  result.absorbed_power = absorbed;
  result.escaped_power = mean.escaped;
  result.unshot_power = mean.unshot_power;
  result.unshot_fraction = mean.power_in > 0 ? mean.unshot_power / mean.power_in : 0.0;
  result.converged = result.unshot_fraction <= options.tolerance;
  const double in = emitted + direct_power;
  result.balance_residual = in > 0 ? std::abs(in - absorbed - mean.escaped - mean.unshot_power) / in : 0.0;
  const double mean_rho = area > 0 ? reflectance_area / area : 0.0;
  result.error_estimate =
      result.unshot_fraction / (1.0 - mean_rho) + (mean.shot_total > 0 ? mean.quadrature / mean.shot_total : 0.0);
  return result;
}

}  // namespace shadow
