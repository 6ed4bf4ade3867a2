// SPDX-License-Identifier: GPL-3.0-or-later
// Progressive refinement (shooting) radiosity on elements cut from the exact lit and shadowed
// fragments of the direct light (docs/radiosity.md).
#include <shadow/radiosity.hpp>

#include "runtime/parallel.hpp"
#include "radiosity/elements.hpp"
#include "radiosity/hierarchy.hpp"
#include "radiosity/receivers.hpp"

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

using radiosity::Element;
using radiosity::Patch;
using radiosity::Receivers;

/// RadiosityMethod::automatic takes the hierarchy above this many patches: below it, shooting
/// is as fast and needs no approximation of far links (docs/radiosity.md).
constexpr std::size_t kAutoHierarchical = 4000;

/// Twice the square root of the median face area: the hierarchical method's longest patch edge.
double typical_patch_edge(const Scene& scene) {
  std::vector<double> areas;
  for (const Face& face : scene.faces)
    if (!face.degenerate && face.vertices.size() >= 3) areas.push_back(0.5 * glm::length(radiosity::newell_normal(face.vertices)));
  if (areas.empty()) return 0.0;
  std::nth_element(areas.begin(), areas.begin() + static_cast<std::ptrdiff_t>(areas.size() / 2), areas.end());
  return 2.0 * std::sqrt(areas[areas.size() / 2]);
}

void check_options(const RadiosityOptions& o, const Scene& scene) {
  if (!(o.max_element_area >= 0.0) || !std::isfinite(o.max_element_area))
    throw InputError({"", "max_element_area"}, "max_element_area must be a finite number >= 0 (m^2)");
  if (!(o.patch_area >= 0.0) || !std::isfinite(o.patch_area))
    throw InputError({"", "patch_area"}, "patch_area must be a finite number >= 0 (m^2)");
  if (!(o.tolerance > 0.0) || !(o.tolerance < 1.0))
    throw InputError({"", "tolerance"}, "tolerance must be in (0, 1): the unshot fraction to stop at");
  // Below 0.1 almost every pair of patches is near: the links grow as their square.
  if (!(o.link_separation >= 0.1) || !(o.link_separation < 1.0))
    throw InputError({"", "link_separation"}, "link_separation must be in [0.1, 1)");
  if (o.method == RadiosityMethod::hierarchical && o.exact_visibility)
    throw InputError({"", "exact_visibility"}, "exact_visibility is for the shooting method (it checks the "
                                               "visibility in doubles); the hierarchical method takes rays for far links");
  if (o.link_rays < 1 || o.link_rays > 1024) throw InputError({"", "link_rays"}, "link_rays must be in [1, 1024]");
  runtime::checked_threads(o.threads);
  if (!o.face_irradiance.empty()) {
    if (o.face_irradiance.size() != scene.faces.size())
      throw InputError({"", "face_irradiance"}, "face_irradiance has " + std::to_string(o.face_irradiance.size()) +
                                                    " values for " + std::to_string(scene.faces.size()) + " faces");
    for (std::size_t f = 0; f < scene.faces.size(); ++f)
      if (!(o.face_irradiance[f] >= 0.0) || !std::isfinite(o.face_irradiance[f]))
        throw InputError({"", "face_irradiance"}, "face_irradiance of face " + std::to_string(f) +
                                                      " must be a finite number >= 0");
  }
  if (!o.face_reflectance.empty()) {
    if (o.face_reflectance.size() != scene.faces.size())
      throw InputError({"", "face_reflectance"}, "face_reflectance has " + std::to_string(o.face_reflectance.size()) +
                                                     " values for " + std::to_string(scene.faces.size()) + " faces");
    for (std::size_t f = 0; f < scene.faces.size(); ++f)
      if (!(o.face_reflectance[f] >= 0.0 && o.face_reflectance[f] < 1.0))
        throw InputError({"", "face_reflectance"}, "face_reflectance of face " + std::to_string(f) + " must be in [0, 1)");
  }
}

/// Each face's area-weighted mean of each light's direct irradiance.
void fill_light_means(const std::vector<Element>& elements, const std::vector<std::vector<double>>& by_light,
                      RadiosityResult& result) {
  for (FaceRadiosity& face : result.faces) face.direct_irradiance_by_light.assign(by_light.size(), 0.0);
  for (std::size_t l = 0; l < by_light.size(); ++l)
    for (std::size_t i = 0; i < elements.size(); ++i)
      result.faces[elements[i].face].direct_irradiance_by_light[l] += by_light[l][i] * elements[i].area;
  for (FaceRadiosity& face : result.faces)
    if (face.area > 0)
      for (double& h : face.direct_irradiance_by_light) h /= face.area;
}

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

/// Gathers (Jacobi) until the power that the last step added is at most the tolerance of the
/// power put in. Each step's balance is exact: with b the radiosities before it and h, b' after,
/// emitted + direct = absorbed (h) + escaped (what b sent that no element received) + unshot
/// (b' - b, what the next step will send).
void iterate(Channel& c, const radiosity::Hierarchy& hierarchy, const std::vector<Element>& elements,
             const std::vector<double>& emit, const std::vector<double>& direct, const RadiosityOptions& options,
             const std::function<void(const Channel&, bool)>& report) {
  const std::size_t n = elements.size();
  std::vector<double> h;
  const std::size_t limit = options.max_shots > 0 ? options.max_shots : 10000;
  while (c.power_in > 0.0 && c.unshot_power > options.tolerance * c.power_in && c.shots < limit) {
    hierarchy.gather(c.b, direct, h);
    double leaving = 0.0, received = 0.0, unshot = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      const double a = elements[i].area, b = emit[i] + c.rho[i] * h[i];
      leaving += c.b[i] * a;
      received += (h[i] - direct[i]) * a;
      unshot += (b - c.b[i]) * a;
      c.b[i] = b;
    }
    c.h.swap(h);
    c.escaped = leaving - received;
    c.unshot_power = unshot;
    ++c.shots;
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
  check_options(options, scene);
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
  // Shooting's patches first (unless the hierarchy was asked for): their count decides `auto`.
  if (options.method != RadiosityMethod::hierarchical)
    radiosity::make_elements(scene, fragments, options.max_element_area, patch_area, 0.0, patches, elements);
  const bool hierarchical =
      options.method == RadiosityMethod::hierarchical ||
      (options.method == RadiosityMethod::automatic && !options.exact_visibility && patches.size() > kAutoHierarchical);
  if (hierarchical) {
    // The hierarchy links groups by their radius: long slivers (a ground's triangles between the
    // holes of its lit part) would be near everything. Patches no longer than twice the typical
    // face's side keep the near links about constant per patch.
    patches.clear();
    elements.clear();
    radiosity::make_elements(scene, fragments, options.max_element_area, patch_area, typical_patch_edge(scene), patches,
                             elements);
  }
  const std::size_t n = elements.size();
  Receivers receivers(scene, threads, options.exact_visibility);
  std::vector<double> direct(n, 0.0);
  std::vector<std::vector<double>> direct_by_light;
  if (options.face_irradiance.empty()) {
    direct_by_light = radiosity::direct_irradiance(scene, fragments, elements, receivers.normals(), options.threads);
    for (const std::vector<double>& light : direct_by_light)
      for (std::size_t i = 0; i < n; ++i) direct[i] += light[i];
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
    options.progress({c.shots, c.power_in > 0 ? c.unshot_power / c.power_in : 0.0, 1.0, hierarchical});
  };
  std::unique_ptr<radiosity::Hierarchy> hierarchy;
  std::unique_ptr<FactorCache> cache;
  if (hierarchical) {
    radiosity::HierarchyOptions ho;
    ho.separation = options.link_separation;
    ho.rays = options.link_rays;
    ho.threads = threads;
    if (options.progress)
      ho.progress = [&](double done) {
        const auto now = std::chrono::steady_clock::now();
        if (now - last < std::chrono::milliseconds(500)) return;
        last = now;
        options.progress({0, 1.0, done, true});
      };
    std::vector<char> can_emit(patches.size(), 0);
    for (std::size_t p = 0; p < patches.size(); ++p)
      for (std::size_t i = patches[p].first; i < patches[p].first + patches[p].count; ++i) {
        const Material& m = scene.material_of(elements[i].face);
        const double most = std::max({rho[i], m.reflectance_rgb.x, m.reflectance_rgb.y, m.reflectance_rgb.z});
        if (emit[i] > 0.0 || (most > 0.0 && (options.face_reflectance.empty() || rho[i] > 0.0))) can_emit[p] = 1;
      }
    hierarchy = std::make_unique<radiosity::Hierarchy>(patches, elements, receivers, can_emit, ho);
  } else {
    cache = std::make_unique<FactorCache>(receivers, patches, elements, threads);
  }
  // Colour: the same solution per channel with that channel's reflectance; the form factors
  // (the cache's rows, or the hierarchy's links) are shared.
  const auto solve = [&](Channel& c, const std::function<void(const Channel&, bool)>& progress) {
    if (hierarchy)
      iterate(c, *hierarchy, elements, emit, direct, options, progress);
    else
      shoot(c, patches, elements, *cache, options, progress);
  };
  Channel mean = start_channel(elements, rho, emit, direct);
  solve(mean, report);
  std::array<Channel, 3> rgb;
  if (colour)
    for (int k = 0; k < 3; ++k) {
      std::vector<double> rho_k(n);
      for (std::size_t i = 0; i < n; ++i) rho_k[i] = channel_reflectance(scene.material_of(elements[i].face), k);
      rgb[static_cast<std::size_t>(k)] = start_channel(elements, rho_k, emit, direct);
      solve(rgb[static_cast<std::size_t>(k)], {});
    }
  if (hierarchy) {
    result.hierarchical = true;
    result.iterations = mean.shots;
    result.near_links = hierarchy->near_links();
    result.far_links = hierarchy->far_links();
  }

  result.shots = hierarchy ? 0 : mean.shots;
  const Totals totals = fill_arrays(scene, elements, direct, rho, emit, mean.b, mean.h, result);
  fill_light_means(elements, direct_by_light, result);
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
  result.error_estimate = result.unshot_fraction / (1.0 - mean_rho) +
                          (hierarchy ? hierarchy->link_error(mean.b)
                                     : (mean.shot_total > 0 ? mean.quadrature / mean.shot_total : 0.0));
  return result;
}

}  // namespace shadow
