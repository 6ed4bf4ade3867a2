// SPDX-License-Identifier: GPL-3.0-or-later
// Progressive refinement (shooting) radiosity on elements cut from the exact lit and shadowed
// fragments of the direct light (docs/radiosity.md).
#include <shadow/radiosity.hpp>

#include "runtime/parallel.hpp"
#include "radiosity/elements.hpp"
#include "radiosity/hierarchy.hpp"
#include "radiosity/receivers.hpp"
#include "radiosity/refinement.hpp"

#include <shadow/area_lights.hpp>
#include <shadow/error.hpp>
#include <shadow/lighting.hpp>
#include <shadow/shadows.hpp>

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
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

/// The most elements a solve makes (some 200 bytes each with their patches and links' share:
/// a few GB).
constexpr std::size_t kMaxElements = std::size_t{1} << 24;

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
  if (!(o.refine_tolerance >= 0.0) || !(o.refine_tolerance < 1.0))
    throw InputError({"", "refine_tolerance"}, "refine_tolerance must be in [0, 1): the relative error of the "
                                               "element field to refine to (0: no adaptive refinement)");
  if (o.refine_passes < 1 || o.refine_passes > 8)
    throw InputError({"", "refine_passes"}, "refine_passes must be in [1, 8]");
  if (o.refine_tolerance > 0.0 && o.method == RadiosityMethod::hierarchical)
    throw InputError({"", "refine_tolerance"}, "adaptive refinement is for the shooting method (the hierarchy's far "
                                               "links carry no gradient)");
  // An element area far below the scene's (a unit slip: 1e-9 for 1e-3) asked for some 1e10
  // elements, and the process grew until the system killed it, with no word. Refused before any
  // is made: no element is larger than max_element_area, so the faces' area over it is a lower
  // bound on their count.
  if (o.max_element_area > 0.0) {
    double total = 0.0;
    for (const Face& face : scene.faces)
      if (!face.degenerate && face.vertices.size() >= 3) total += 0.5 * glm::length(radiosity::newell_normal(face.vertices));
    const double at_least = total / o.max_element_area;
    if (at_least > static_cast<double>(kMaxElements)) {
      char text[256];
      std::snprintf(text, sizeof text,
                    "%g m^2 would cut the scene's %.6g m^2 into at least %.3g elements (at most %zu "
                    "are made): choose a larger element area",
                    o.max_element_area, total, at_least, kMaxElements);
      throw InputError({"", "max_element_area"}, text);
    }
  }
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

/// Each face's area-weighted mean of each light's direct irradiance (`direct`) and, when
/// `irradiance` is not empty, of each light's irradiance (direct and reflected).
void fill_light_means(const std::vector<Element>& elements, const std::vector<std::vector<double>>& direct,
                      const std::vector<std::vector<double>>& irradiance, RadiosityResult& result) {
  const auto face_means = [&](const std::vector<std::vector<double>>& by_light,
                              std::vector<double> FaceRadiosity::*field) {
    for (FaceRadiosity& face : result.faces) (face.*field).assign(by_light.size(), 0.0);
    for (std::size_t l = 0; l < by_light.size(); ++l)
      for (std::size_t i = 0; i < elements.size(); ++i)
        (result.faces[elements[i].face].*field)[l] += by_light[l][i] * elements[i].area;
    for (FaceRadiosity& face : result.faces)
      if (face.area > 0)
        for (double& h : face.*field) h /= face.area;
  };
  face_means(direct, &FaceRadiosity::direct_irradiance_by_light);
  face_means(irradiance, &FaceRadiosity::irradiance_by_light);
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
  /// With adaptive refinement: H's spread over each element (two per element, refinement.hpp),
  /// the direct light's and every shot's summed.
  std::vector<double> spread;
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

  /// Patch k's row: the form factor from each element to it and its quadrature change (and,
  /// with `spread`, the factor's spread over each element: two values per element).
  void row(std::size_t k, std::vector<double>& factor, std::vector<double>& quad, std::vector<float>* spread) {
    if (!factor_[k].empty() && (!spread || !spread_[k].empty())) {
      if (stale_[k]) fill_new(k);
      factor = factor_[k];
      quad.assign(quad_[k].begin(), quad_[k].end());
      if (spread) *spread = spread_[k];
      return;
    }
    receivers_.receive(patches_, elements_, patches_[k], threads_, factor, quad, spread);
    const std::size_t bytes = elements_.size() * (sizeof(double) + sizeof(float) + (spread ? 2 * sizeof(float) : 0));
    if (factor_[k].empty() && bytes_ + bytes <= kBudget) {
      factor_[k] = factor;
      quad_[k].assign(quad.begin(), quad.end());
      if (spread) spread_[k] = *spread;
      stale_[k] = 0;
      bytes_ += bytes;
    }
  }

  /// After adaptive refinement split elements (`origin`: refinement.hpp's split_elements): the
  /// rows kept are carried over to the new elements, the pieces' entries computed when a row is
  /// next asked for (the elements kept whole keep theirs: the same triangles, the same patches).
  void remap(const std::vector<std::size_t>& origin) {
    fresh_.assign(origin.size(), 0);
    for (std::size_t i = 0; i < origin.size(); ++i) fresh_[i] = origin[i] == SIZE_MAX;
    bytes_ = 0;
    for (std::size_t k = 0; k < factor_.size(); ++k) {
      if (factor_[k].empty()) continue;
      if (stale_[k]) {  // not asked for since the last split: its pieces' entries were never made
        factor_[k] = {}, quad_[k] = {}, spread_[k] = {};
        stale_[k] = 0;
        continue;
      }
      const std::size_t bytes = origin.size() * (sizeof(double) + sizeof(float) + (spread_[k].empty() ? 0 : 2 * sizeof(float)));
      if (bytes_ + bytes > kBudget) {  // over the budget now that rows are longer: computed again when asked
        factor_[k] = {}, quad_[k] = {}, spread_[k] = {};
        continue;
      }
      bytes_ += bytes;
      std::vector<double> factor(origin.size(), 0.0);
      std::vector<float> quad(origin.size(), 0.0f), spread(spread_[k].empty() ? 0 : 2 * origin.size(), 0.0f);
      for (std::size_t i = 0; i < origin.size(); ++i) {
        if (origin[i] == SIZE_MAX) continue;
        factor[i] = factor_[k][origin[i]];
        quad[i] = quad_[k][origin[i]];
        if (!spread.empty()) spread[2 * i] = spread_[k][2 * origin[i]], spread[2 * i + 1] = spread_[k][2 * origin[i] + 1];
      }
      factor_[k].swap(factor), quad_[k].swap(quad), spread_[k].swap(spread);
      stale_[k] = 1;
    }
  }

 private:
  static constexpr std::size_t kBudget = std::size_t(512) << 20;
  Receivers& receivers_;
  const std::vector<Patch>& patches_;
  const std::vector<Element>& elements_;
  unsigned threads_;
  std::vector<std::vector<double>> factor_;
  /// Row k's entries for the new elements (fresh_) computed and put in.
  void fill_new(std::size_t k) {
    std::vector<double> factor, quad;
    std::vector<float> spread;
    const bool with_spread = !spread_[k].empty();
    receivers_.receive(patches_, elements_, patches_[k], threads_, factor, quad, with_spread ? &spread : nullptr,
                       &fresh_);
    for (std::size_t i = 0; i < fresh_.size(); ++i) {
      if (!fresh_[i]) continue;
      factor_[k][i] = factor[i];
      quad_[k][i] = static_cast<float>(quad[i]);
      if (with_spread) spread_[k][2 * i] = spread[2 * i], spread_[k][2 * i + 1] = spread[2 * i + 1];
    }
    stale_[k] = 0;
  }

  std::vector<std::vector<float>> quad_, spread_ = std::vector<std::vector<float>>(patches_.size());
  std::vector<char> stale_ = std::vector<char>(patches_.size(), 0), fresh_;
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
  std::vector<float> spread;
  const bool with_spread = !c.spread.empty();
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
    cache.row(k, factor, quad, with_spread ? &spread : nullptr);
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
      if (with_spread) c.spread[2 * i] += db * spread[2 * i], c.spread[2 * i + 1] += db * spread[2 * i + 1];
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

/// Each element's direct irradiance: in all, per light, and (refining) its spread over the element.
struct DirectLight {
  std::vector<double> total, spread;
  std::vector<std::vector<double>> by_light;
};

DirectLight light_elements(const Scene& scene, const RadiosityOptions& options, const std::vector<Fragment>& fragments,
                           const std::vector<Element>& elements, const Receivers& receivers, bool spread) {
  DirectLight d;
  const std::size_t n = elements.size();
  d.total.assign(n, 0.0);
  if (options.face_irradiance.empty()) {
    d.by_light = radiosity::direct_irradiance(scene, fragments, elements, receivers.normals(), options.threads,
                                              spread ? &d.spread : nullptr);
    for (const std::vector<double>& light : d.by_light)
      for (std::size_t i = 0; i < n; ++i) d.total[i] += light[i];
  } else {
    // One value per face: no spread within a face.
    for (std::size_t i = 0; i < n; ++i) d.total[i] = options.face_irradiance[elements[i].face];
  }
  if (spread) d.spread.resize(2 * n, 0.0);
  return d;
}

/// light_elements() after adaptive refinement: the elements kept whole (`origin`, refinement.hpp)
/// keep `before`'s values, the pieces' are computed.
DirectLight relight(const Scene& scene, const RadiosityOptions& options, const std::vector<Fragment>& fragments,
                    const std::vector<Element>& elements, const Receivers& receivers, const DirectLight& before,
                    const std::vector<std::size_t>& origin) {
  std::vector<Element> pieces;
  for (std::size_t i = 0; i < elements.size(); ++i)
    if (origin[i] == SIZE_MAX) pieces.push_back(elements[i]);
  const DirectLight part = light_elements(scene, options, fragments, pieces, receivers, !before.spread.empty());
  DirectLight d;
  const std::size_t n = elements.size();
  d.total.resize(n);
  d.spread.resize(before.spread.empty() ? 0 : 2 * n);
  d.by_light.assign(before.by_light.size(), std::vector<double>(n));
  for (std::size_t i = 0, k = 0; i < n; ++i) {
    const bool kept = origin[i] != SIZE_MAX;
    const std::size_t j = kept ? origin[i] : k++;
    const DirectLight& from = kept ? before : part;
    d.total[i] = from.total[j];
    if (!d.spread.empty()) d.spread[2 * i] = from.spread[2 * j], d.spread[2 * i + 1] = from.spread[2 * j + 1];
    for (std::size_t l = 0; l < d.by_light.size(); ++l) d.by_light[l][i] = from.by_light[l][j];
  }
  return d;
}

/// Each element's reflectance and emittance, their mean reflectance, and whether any material
/// is coloured.
struct Surfaces {
  std::vector<double> rho, emit;
  double mean_rho = 0.0;
  bool colour = false;
};

Surfaces surfaces_of(const Scene& scene, const RadiosityOptions& options, const std::vector<Element>& elements) {
  Surfaces s;
  const std::size_t n = elements.size();
  s.rho.resize(n);
  s.emit.resize(n);
  double reflectance_area = 0.0, area = 0.0;
  const bool given = !options.face_reflectance.empty();
  for (std::size_t i = 0; i < n; ++i) {
    const Material& m = scene.material_of(elements[i].face);
    s.rho[i] = given ? options.face_reflectance[elements[i].face] : m.reflectance;
    s.emit[i] = m.emittance;
    reflectance_area += s.rho[i] * elements[i].area;
    area += elements[i].area;
    for (int k = 0; k < 3 && !given; ++k) s.colour = s.colour || channel_reflectance(m, k) != m.reflectance;
  }
  s.mean_rho = area > 0 ? reflectance_area / area : 0.0;
  return s;
}

/// The hierarchy's links over `patches` (groups that cannot emit link nothing).
std::unique_ptr<radiosity::Hierarchy> make_hierarchy(const Scene& scene, const RadiosityOptions& options,
                                                     const std::vector<Patch>& patches,
                                                     const std::vector<Element>& elements, const Surfaces& surfaces,
                                                     Receivers& receivers, unsigned threads,
                                                     std::function<void(double)> progress) {
  radiosity::HierarchyOptions ho;
  ho.separation = options.link_separation;
  ho.rays = options.link_rays;
  ho.threads = threads;
  ho.progress = std::move(progress);
  std::vector<char> can_emit(patches.size(), 0);
  for (std::size_t p = 0; p < patches.size(); ++p)
    for (std::size_t i = patches[p].first; i < patches[p].first + patches[p].count; ++i) {
      const Material& m = scene.material_of(elements[i].face);
      const double rho = surfaces.rho[i];
      const double most = std::max({rho, m.reflectance_rgb.x, m.reflectance_rgb.y, m.reflectance_rgb.z});
      if (surfaces.emit[i] > 0.0 || (most > 0.0 && (options.face_reflectance.empty() || rho > 0.0))) can_emit[p] = 1;
    }
  return std::make_unique<radiosity::Hierarchy>(patches, elements, receivers, can_emit, ho);
}

/// The estimated relative error of the element field from the solution's spread (refinement.hpp);
/// splits the elements with the largest errors when it is above the tolerance and returns whether
/// it did.
bool refine_once(const RadiosityOptions& options, int pass, std::vector<Patch>& patches,
                 std::vector<Element>& elements, const Channel& solution, RadiosityResult& result,
                 std::vector<std::size_t>& origin) {
  const std::vector<double> errors = radiosity::element_errors(elements, solution.spread);
  double error = 0.0, norm = 0.0;
  for (std::size_t i = 0; i < elements.size(); ++i) {
    error += errors[i];
    norm += solution.h[i] * solution.h[i] * elements[i].area;
  }
  result.discretization_error = norm > 0 ? std::sqrt(error / norm) : 0.0;
  const double target = options.refine_tolerance * options.refine_tolerance * norm;
  if (error <= target || pass >= options.refine_passes) return false;
  const std::vector<char> marked = radiosity::mark_for_split(elements, errors, target, options.refine_passes);
  if (std::find(marked.begin(), marked.end(), 1) == marked.end()) return false;
  radiosity::split_elements(patches, elements, marked, origin);
  result.refine_passes = static_cast<std::size_t>(pass) + 1;
  return true;
}

/// Each light's irradiance per element, direct and reflected: the equation is linear in its
/// sources, so one more solution per light with that light alone (none when one light is the only
/// source: `solution`'s). `solve(channel, emittance, direct light)` solves a channel.
std::vector<std::vector<double>> light_shares(
    const std::vector<Element>& elements, const DirectLight& direct, const Surfaces& surfaces, const Channel& solution,
    const std::function<void(Channel&, const std::vector<double>&, const std::vector<double>&)>& solve) {
  std::vector<std::vector<double>> shares;
  const bool emitters = std::any_of(surfaces.emit.begin(), surfaces.emit.end(), [](double e) { return e > 0.0; });
  if (direct.by_light.size() == 1 && !emitters) return {solution.h};
  const std::vector<double> none(elements.size(), 0.0);
  for (const std::vector<double>& light : direct.by_light) {
    Channel alone = start_channel(elements, surfaces.rho, none, light);
    solve(alone, none, light);
    shares.push_back(std::move(alone.h));
  }
  return shares;
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
  const bool refining = options.refine_tolerance > 0.0;
  const bool hierarchical =
      options.method == RadiosityMethod::hierarchical ||
      (options.method == RadiosityMethod::automatic && !options.exact_visibility && patches.size() > kAutoHierarchical);
  if (hierarchical && refining)
    throw InputError({"", "refine_tolerance"}, std::to_string(patches.size()) +
                                                   " patches take the hierarchical method, which has no adaptive "
                                                   "refinement; choose the shooting method to refine (slow at this size)");
  if (hierarchical) {
    // The hierarchy links groups by their radius: long slivers (a ground's triangles between the
    // holes of its lit part) would be near everything. Patches no longer than twice the typical
    // face's side keep the near links about constant per patch.
    patches.clear();
    elements.clear();
    radiosity::make_elements(scene, fragments, options.max_element_area, patch_area, typical_patch_edge(scene), patches,
                             elements);
  }
  Receivers receivers(scene, threads, options.exact_visibility);
  RadiosityResult result;
  result.initial_elements = elements.size();
  auto last = std::chrono::steady_clock::now();
  const auto report = [&](const Channel& c, bool force) {
    if (!options.progress) return;
    const auto now = std::chrono::steady_clock::now();
    if (!force && now - last < std::chrono::milliseconds(500)) return;
    last = now;
    options.progress({c.shots, c.power_in > 0 ? c.unshot_power / c.power_in : 0.0, 1.0, hierarchical});
  };
  const auto links_progress = [&](double done) {
    const auto now = std::chrono::steady_clock::now();
    if (now - last < std::chrono::milliseconds(500)) return;
    last = now;
    options.progress({0, 1.0, done, true});
  };
  std::unique_ptr<radiosity::Hierarchy> hierarchy;
  std::unique_ptr<FactorCache> cache;
  DirectLight direct = light_elements(scene, options, fragments, elements, receivers, refining);
  Surfaces surfaces = surfaces_of(scene, options, elements);
  Channel mean;
  // Colour: the same solution per channel with that channel's reflectance; the form factors
  // (the cache's rows, or the hierarchy's links) are shared.
  const auto solve_for = [&](Channel& c, const std::vector<double>& emit, const std::vector<double>& light,
                             const std::function<void(const Channel&, bool)>& progress) {
    if (hierarchy)
      iterate(c, *hierarchy, elements, emit, light, options, progress);
    else
      shoot(c, patches, elements, *cache, options, progress);
  };
  const auto solve = [&](Channel& c, const std::function<void(const Channel&, bool)>& progress) {
    solve_for(c, surfaces.emit, direct.total, progress);
  };
  if (hierarchical)
    hierarchy = make_hierarchy(scene, options, patches, elements, surfaces, receivers, threads,
                               options.progress ? std::function<void(double)>(links_progress) : nullptr);
  else
    cache = std::make_unique<FactorCache>(receivers, patches, elements, threads);
  // Adaptive refinement solves again on the split elements, from the start: the form factors of
  // the elements kept whole come from the cache, only the pieces' are computed.
  std::vector<std::size_t> origin;
  for (int pass = 0;; ++pass) {
    mean = start_channel(elements, surfaces.rho, surfaces.emit, direct.total);
    mean.spread = direct.spread;
    solve(mean, report);
    if (!refining || !refine_once(options, pass, patches, elements, mean, result, origin)) break;
    cache->remap(origin);
    direct = relight(scene, options, fragments, elements, receivers, direct, origin);
    surfaces = surfaces_of(scene, options, elements);
  }
  const std::size_t n = elements.size();
  std::array<Channel, 3> rgb;
  if (surfaces.colour)
    for (int k = 0; k < 3; ++k) {
      std::vector<double> rho_k(n);
      for (std::size_t i = 0; i < n; ++i) rho_k[i] = channel_reflectance(scene.material_of(elements[i].face), k);
      rgb[static_cast<std::size_t>(k)] = start_channel(elements, rho_k, surfaces.emit, direct.total);
      solve(rgb[static_cast<std::size_t>(k)], {});
    }
  const std::vector<std::vector<double>> light_h =
      options.per_light && scene.lights.size() <= radiosity::kFewLights ? light_shares(elements, direct, surfaces, mean, [&](Channel& c, const std::vector<double>& e,
                                                                             const std::vector<double>& light) {
        solve_for(c, e, light, {});
      })
                        : std::vector<std::vector<double>>();
  if (hierarchy) {
    result.hierarchical = true;
    result.iterations = mean.shots;
    result.near_links = hierarchy->near_links();
    result.far_links = hierarchy->far_links();
  }

  result.shots = hierarchy ? 0 : mean.shots;
  const Totals totals = fill_arrays(scene, elements, direct.total, surfaces.rho, surfaces.emit, mean.b, mean.h, result);
  fill_light_means(elements, direct.by_light, light_h, result);
  const bool colour = surfaces.colour;
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
  result.error_estimate = result.unshot_fraction / (1.0 - surfaces.mean_rho) +
                          (hierarchy ? hierarchy->link_error(mean.b)
                                     : (mean.shot_total > 0 ? mean.quadrature / mean.shot_total : 0.0));
  return result;
}

}  // namespace shadow
