// SPDX-License-Identifier: GPL-3.0-or-later
#include "radiosity/elements.hpp"

#include "radiosity/contacts.hpp"
#include "runtime/parallel.hpp"

#include <shadow/area_lights.hpp>
#include <shadow/lighting.hpp>

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <utility>

namespace shadow::radiosity {
Element make_element(std::size_t face, const Triangle& t, std::size_t fragment, std::size_t patch) {
  Element e;
  e.patch = patch;
  e.face = face;
  e.triangle = t;
  e.area = triangle_area(t);
  e.centroid = (t[0] + t[1] + t[2]) / 3.0;
  for (const glm::dvec3& v : t) e.radius = std::max(e.radius, glm::length(v - e.centroid));
  e.fragment = fragment;
  return e;
}

namespace {

/// The most segments of later lights' shadow boundaries that cut one face: each cuts every
/// triangle its line crosses (cut_along), so a face under a city's shadows from several lights
/// would be sliced into strips; beyond this the face keeps the first light's mesh alone.
constexpr std::size_t kMostBoundarySegments = 4096;

/// Appends to `cuts[f]` the shadow boundaries of the later hard lights on each face f (scenes of
/// at most kFewLights lights): their lit fragments' edges, less those that two lit fragments
/// share.
void add_shadow_boundaries(const Scene& scene, const std::vector<Fragment>& fragments,
                           std::vector<std::vector<Segment>>& cuts) {
  if (scene.lights.size() > kFewLights) return;
  std::map<std::pair<std::size_t, std::size_t>, std::vector<Segment>> edges;  // (face, light)
  for (const Fragment& fragment : fragments) {
    const std::size_t l = fragment.light_id;
    if (l == 0 || l >= scene.lights.size() || scene.lights[l].is_extended() || !fragment.lit ||
        fragment.face_id >= scene.faces.size())
      continue;
    std::vector<Segment>& list = edges[{fragment.face_id, l}];
    const std::vector<glm::dvec3>& p = fragment.polygon;
    for (std::size_t i = 0; i < p.size(); ++i) list.push_back({p[i], p[(i + 1) % p.size()]});
  }
  std::vector<std::vector<Segment>> boundaries(cuts.size());
  for (auto& [key, list] : edges) {
    // An edge between two lit pieces is met once each way: neither is a boundary.
    std::map<std::array<double, 6>, int> count;
    const auto key_of = [](const glm::dvec3& a, const glm::dvec3& b) {
      return std::array<double, 6>{a.x, a.y, a.z, b.x, b.y, b.z};
    };
    for (const Segment& s : list) ++count[key_of(s.a, s.b)];
    for (const Segment& s : list)
      if (count.count(key_of(s.b, s.a)) == 0) boundaries[key.first].push_back(s);
  }
  for (std::size_t f = 0; f < cuts.size(); ++f)
    if (boundaries[f].size() <= kMostBoundarySegments)
      cuts[f].insert(cuts[f].end(), boundaries[f].begin(), boundaries[f].end());
}

void add_element(std::vector<Element>& out, std::size_t face, const Triangle& t, std::size_t fragment,
                 std::size_t patch) {
  Element e = make_element(face, t, fragment, patch);
  if (e.area > 0.0) out.push_back(e);
}

}  // namespace

void make_elements(const Scene& scene, const std::vector<Fragment>& fragments, double max_area, double patch_area,
                   double max_patch_edge, std::vector<Patch>& patches, std::vector<Element>& elements) {
  std::vector<std::vector<std::size_t>> by_face(scene.faces.size());
  for (std::size_t i = 0; i < fragments.size(); ++i)
    if (fragments[i].light_id == 0 && fragments[i].face_id < scene.faces.size()) by_face[fragments[i].face_id].push_back(i);
  // Cut along where other faces meet each face: a floor element under a box's wall would
  // average the lit floor with the closed-off part beneath the box.
  std::vector<std::vector<Segment>> contacts = contact_segments(scene);
  // And along the other lights' shadow boundaries: a patch across one would shoot the light of
  // its lit part from its shadowed part too (a wall beside the shadow then gets twice its share).
  add_shadow_boundaries(scene, fragments, contacts);
  std::vector<Triangle> coarse, fine, cut;
  for (std::size_t f = 0; f < scene.faces.size(); ++f) {
    const Face& face = scene.faces[f];
    if (face.degenerate || face.vertices.size() < 3) continue;
    const glm::dvec3 n = newell_normal(face.vertices);
    auto add_polygon = [&](const std::vector<glm::dvec3>& polygon, std::size_t fragment) {
      cut.clear();
      for (const Triangle& t : triangulate(polygon)) {
        // With an edge limit, shorten first: a whole ground cut along every box standing on it
        // would be sliced into strips across the city (half a million elements for 1,024 boxes).
        coarse.clear();
        refine(t, 0.0, coarse, max_patch_edge);
        for (const Triangle& piece : coarse) cut_along(piece, glm::normalize(n), contacts[f], cut);
      }
      for (const Triangle& t : cut) {
        coarse.clear();
        refine(t, patch_area, coarse, max_patch_edge);
        for (const Triangle& c : coarse) {
          Patch p;
          p.face = f;
          p.triangle = c;
          p.area = triangle_area(c);
          p.centroid = (c[0] + c[1] + c[2]) / 3.0;
          for (const glm::dvec3& v : c) p.radius = std::max(p.radius, glm::length(v - p.centroid));
          p.first = elements.size();
          fine.clear();
          refine(c, max_area, fine);
          for (const Triangle& e : fine) add_element(elements, f, e, fragment, patches.size());
          p.count = elements.size() - p.first;
          if (p.count > 0) patches.push_back(p);
        }
      }
    };
    if (by_face[f].empty()) add_polygon(face.vertices, SIZE_MAX);
    for (std::size_t i : by_face[f]) add_polygon(fragments[i].polygon, i);
  }
}

std::vector<std::vector<double>> direct_irradiance(const Scene& scene, const std::vector<Fragment>& fragments,
                                                   const std::vector<Element>& elements,
                                                   const std::vector<glm::dvec3>& normals, unsigned threads,
                                                   std::vector<double>* spread) {
  std::vector<std::vector<double>> by_light(scene.lights.size(), std::vector<double>(elements.size(), 0.0));
  if (spread) spread->assign(2 * elements.size(), 0.0);
  // The spread of three values at the interior points (4 a + b + c) / 6 added to element i's.
  const auto add_spread = [&](std::size_t i, double h0, double h1, double h2) {
    const double mean = (h0 + h1 + h2) / 3.0;
    (*spread)[2 * i] += h0 - mean;
    (*spread)[2 * i + 1] += h1 - mean;
  };
  // An extended light's irradiance varies across a penumbra cell: the mean of the three interior
  // points of the degree-2 triangle rule, each exact.
  std::vector<SurfacePoint> points;  // made when the first extended light needs them
  for (std::size_t l = 0; l < scene.lights.size(); ++l) {
    const Light& light = scene.lights[l];
    std::vector<double>& direct = by_light[l];
    if (light.is_extended()) {
      if (points.empty())
        for (const Element& e : elements)
          for (int c = 0; c < 3; ++c) points.push_back({e.face, interior_point(e.triangle, c)});
      const std::vector<double> h = light_irradiance(scene, light, points, threads);
      for (std::size_t i = 0; i < elements.size(); ++i) {
        direct[i] = (h[3 * i] + h[3 * i + 1] + h[3 * i + 2]) / 3.0;
        if (spread) add_spread(i, h[3 * i], h[3 * i + 1], h[3 * i + 2]);
      }
      continue;
    }
    // The lit fragments of this light per face, with their normals and boxes (a ground under a
    // city has thousands: each element tries only those whose box holds its centroid).
    struct Lit {
      std::size_t fragment;
      glm::dvec3 normal, lo, hi;
    };
    std::vector<std::vector<Lit>> lit(scene.faces.size());
    if (l > 0)
      for (std::size_t i = 0; i < fragments.size(); ++i)
        if (fragments[i].light_id == l && fragments[i].lit && fragments[i].face_id < scene.faces.size()) {
          Lit entry{i, newell_normal(fragments[i].polygon), glm::dvec3(std::numeric_limits<double>::infinity()),
                    glm::dvec3(-std::numeric_limits<double>::infinity())};
          for (const glm::dvec3& v : fragments[i].polygon) entry.lo = glm::min(entry.lo, v), entry.hi = glm::max(entry.hi, v);
          // Widened: a centroid on the plane of a wall may round off it by an ulp or so.
          const glm::dvec3 pad(1e-9 * (glm::length(entry.hi - entry.lo) + glm::length(entry.hi) + glm::length(entry.lo)));
          entry.lo -= pad;
          entry.hi += pad;
          lit[fragments[i].face_id].push_back(entry);
        }
    const auto lit_at = [&](std::size_t face, const glm::dvec3& p) {
      for (const Lit& k : lit[face]) {
        if (p.x < k.lo.x || p.y < k.lo.y || p.z < k.lo.z || p.x > k.hi.x || p.y > k.hi.y || p.z > k.hi.z) continue;
        if (inside_polygon(fragments[k.fragment].polygon, k.normal, p)) return true;
      }
      return false;
    };
    runtime::parallel_for(elements.size(), runtime::resolve_threads(threads), [&](unsigned, std::size_t i) {
      const Element& e = elements[i];
      const bool first = l == 0;
      const bool is_lit = first ? e.fragment != SIZE_MAX && fragments[e.fragment].lit : lit_at(e.face, e.centroid);
      if (is_lit) direct[i] = irradiance(light, e.centroid, normals[e.face]);
      if (!spread) return;
      // The first light's fragments bound the elements (lit or not throughout); a later light's
      // shadow may cross one: its interior points are tested one by one.
      double h[3];
      for (int c = 0; c < 3; ++c) {
        const glm::dvec3 p = interior_point(e.triangle, c);
        h[c] = (first ? is_lit : lit_at(e.face, p)) ? irradiance(light, p, normals[e.face]) : 0.0;
      }
      add_spread(i, h[0], h[1], h[2]);
    });
  }
  return by_light;
}


}  // namespace shadow::radiosity
