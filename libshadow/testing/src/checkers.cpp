// SPDX-License-Identifier: GPL-3.0-or-later
// Reference values, invariant checkers and the approximate-method comparison of
// shadow/testing.hpp. Plain doubles: the exact decisions are the engine's and oracles.cpp's.
#include <shadow/error.hpp>
#include <shadow/testing.hpp>

#include <glm/geometric.hpp>


#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <sstream>
#include <utility>

namespace shadow::testing {
namespace {

using Polygon = std::vector<glm::dvec3>;

/// Newell's normal relative to the first vertex, written here rather than taken from the library:
/// the kit uses the public API only.
glm::dvec3 newell(const Polygon& p) {
  glm::dvec3 n(0.0);
  for (std::size_t a = 0; a < p.size(); ++a) {
    const glm::dvec3 u = p[a] - p[0], v = p[(a + 1) % p.size()] - p[0];
    n += glm::dvec3((u.y - v.y) * (u.z + v.z), (u.z - v.z) * (u.x + v.x), (u.x - v.x) * (u.y + v.y));
  }
  return n;
}

int dominant_axis(const glm::dvec3& n) {
  const glm::dvec3 a = glm::abs(n);
  if (a.x >= a.y && a.x >= a.z) return 0;
  return a.y >= a.z ? 1 : 2;
}

/// Chart point-in-polygon in doubles with the distance to the boundary (for sampling only).
bool inside_chart(const Polygon& poly, int k, const glm::dvec3& p, double* boundary_distance) {
  const int i = (k + 1) % 3, j = (k + 2) % 3;
  bool inside = false;
  double distance = std::numeric_limits<double>::max();
  for (std::size_t a = 0, b = poly.size() - 1; a < poly.size(); b = a++) {
    const double ux = poly[a][i], uy = poly[a][j], wx = poly[b][i], wy = poly[b][j];
    if ((uy > p[j]) != (wy > p[j]) && p[i] < (wx - ux) * (p[j] - uy) / (wy - uy) + ux) inside = !inside;
    const double ex = wx - ux, ey = wy - uy, len2 = ex * ex + ey * ey;
    const double t = len2 > 0 ? std::clamp(((p[i] - ux) * ex + (p[j] - uy) * ey) / len2, 0.0, 1.0) : 0.0;
    distance = std::min(distance, std::hypot(p[i] - (ux + t * ex), p[j] - (uy + t * ey)));
  }
  if (boundary_distance) *boundary_distance = distance;
  return inside;
}

/// Rejection sampling in the chart box, lifted onto the polygon's plane in doubles; `margin`
/// is the smallest distance to the boundary in the chart.
std::vector<glm::dvec3> sample_polygon(const Polygon& poly, std::size_t count, double margin, std::mt19937_64& rng) {
  std::vector<glm::dvec3> points;
  if (poly.size() < 3) return points;
  const glm::dvec3 n = newell(poly);
  const int k = dominant_axis(n);
  if (n[k] == 0) return points;
  const int i = (k + 1) % 3, j = (k + 2) % 3;
  glm::dvec3 lo = poly[0], hi = poly[0], centre(0.0);
  for (const glm::dvec3& v : poly) {
    lo = glm::min(lo, v);
    hi = glm::max(hi, v);
    centre += v;
  }
  centre /= static_cast<double>(poly.size());
  std::uniform_real_distribution<double> ui(lo[i], hi[i]), uj(lo[j], hi[j]);
  for (std::size_t attempt = 0; attempt < 50 * count && points.size() < count; ++attempt) {
    glm::dvec3 p(0.0);
    p[i] = ui(rng);
    p[j] = uj(rng);
    p[k] = centre[k] - (n[i] * (p[i] - centre[i]) + n[j] * (p[j] - centre[j])) / n[k];
    double d = 0;
    if (inside_chart(poly, k, p, &d) && d >= margin) points.push_back(p);
  }
  return points;
}

double diameter(const Polygon& poly) {
  glm::dvec3 lo = poly[0], hi = poly[0];
  for (const glm::dvec3& v : poly) {
    lo = glm::min(lo, v);
    hi = glm::max(hi, v);
  }
  return std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
}

/// The face's name, else where it was defined (its source), else face_<id>.
std::string label(const Scene& scene, std::size_t face_id) {
  const Face& f = scene.faces.at(face_id);
  if (!f.name.empty()) return f.name;
  const std::string where = f.source.to_string();
  return where.empty() ? face_label(scene, face_id) : where;
}

std::string describe(const Scene& scene, std::size_t face_id, std::size_t light_id) {
  std::ostringstream s;
  s << "face " << face_id << " (" << label(scene, face_id) << ") light " << light_id;
  if (light_id < scene.lights.size()) s << " (" << scene.lights[light_id].name << ")";
  return s.str();
}

ShadowResult areas_only(const Scene& scene) {
  ShadowOptions options;
  options.polygons = false;
  options.planes = false;
  return compute_shadows(scene, options);
}

glm::dvec3 quarter_turns(glm::dvec3 v, int x, int y, int z) {
  // Each quarter turn swaps two coordinates and negates one: exact.
  for (int q = ((x % 4) + 4) % 4; q > 0; --q) v = {v.x, -v.z, v.y};
  for (int q = ((y % 4) + 4) % 4; q > 0; --q) v = {v.z, v.y, -v.x};
  for (int q = ((z % 4) + 4) % 4; q > 0; --q) v = {-v.y, v.x, v.z};
  return v;
}

}  // namespace

double exact_lit_area(const Scene& scene, std::size_t face_id, std::size_t light_id) {
  if (face_id >= scene.faces.size())
    throw InputError(SourceLocation{"shadow::testing", ""}, "face " + std::to_string(face_id) + " is not a scene face");
  if (light_id >= scene.lights.size())
    throw InputError(SourceLocation{"shadow::testing", ""}, "light " + std::to_string(light_id) + " is not a scene light");
  Scene one = scene;  // only this face's mesh receives: the engine computes what is asked
  for (std::size_t m = 0; m < one.meshes.size(); ++m) one.meshes[m].receiver = m == scene.faces[face_id].mesh;
  ShadowOptions options;
  options.polygons = false;
  options.planes = false;
  options.lights = {light_id};
  const ShadowResult r = compute_shadows(one, options);
  const FaceLighting* fl = r.find(face_id, light_id);
  return fl ? fl->lit_area : 0.0;
}

double exact_shadow_area(const Scene& scene, std::size_t plane_id, std::size_t light_id) {
  if (plane_id >= scene.planes.size())
    throw InputError(SourceLocation{"shadow::testing", ""}, "plane " + std::to_string(plane_id) + " is not a scene plane");
  if (light_id >= scene.lights.size())
    throw InputError(SourceLocation{"shadow::testing", ""}, "light " + std::to_string(light_id) + " is not a scene light");
  Scene one = scene;
  one.planes = {scene.planes[plane_id]};
  ShadowOptions options;
  options.lights = {light_id};
  for (const PlaneShadow& s : compute_plane_shadows(one, options))
    if (s.light_id == light_id) return s.area;
  return 0.0;
}

std::vector<glm::dvec3> sample_face(const Scene& scene, std::size_t face_id, std::size_t count, std::uint64_t seed) {
  if (face_id >= scene.faces.size())
    throw InputError(SourceLocation{"shadow::testing", ""}, "face " + std::to_string(face_id) + " is not a scene face");
  std::mt19937_64 rng(seed);
  return sample_polygon(scene.faces[face_id].vertices, count, 0.0, rng);
}

Verdict check_partition(const Scene& scene, const ShadowResult& result) {
  std::ostringstream out;
  std::map<std::pair<std::size_t, std::size_t>, std::pair<double, double>> cells;  // all, lit
  for (const Fragment& f : result.fragments) {
    const double drawn = f.polygon.size() >= 3 ? 0.5 * glm::length(newell(f.polygon)) : 0.0;
    // Rounding each vertex to doubles (half an ulp of its coordinates) moves the area by at
    // most the perimeter times that: far from the origin this dominates.
    double perimeter = 0, largest = 0;
    for (std::size_t a = 0; a < f.polygon.size(); ++a) {
      perimeter += glm::length(f.polygon[(a + 1) % f.polygon.size()] - f.polygon[a]);
      largest = std::max({largest, std::abs(f.polygon[a].x), std::abs(f.polygon[a].y), std::abs(f.polygon[a].z)});
    }
    const double rounding = 2 * perimeter * largest * std::numeric_limits<double>::epsilon();
    if (std::abs(drawn - f.area) > 1e-12 * (1.0 + f.area) + rounding)
      out << describe(scene, f.face_id, f.light_id) << " fragment " << f.fragment_id << ": polygon area " << drawn
          << " != stated area " << f.area << "\n";
    // The face's orientation, unless rounding flattened the cell (an exact sliver far below the
    // coordinates' resolution).
    if (f.face_id < scene.faces.size() && drawn > 2 * rounding + 1e-15 * (1.0 + f.area) &&
        glm::dot(newell(f.polygon), newell(scene.faces[f.face_id].vertices)) <= 0)
      out << describe(scene, f.face_id, f.light_id) << " fragment " << f.fragment_id
          << ": polygon turns against its face\n";
    auto& c = cells[{f.face_id, f.light_id}];
    c.first += f.area;
    if (f.lit) c.second += f.area;
  }
  const bool with_fragments = !result.fragments.empty();
  for (const FaceLighting& fl : result.lighting) {
    if (std::abs(fl.lit_area + fl.shadow_area - fl.area) > 4e-16 * fl.area)
      out << describe(scene, fl.face_id, fl.light_id) << ": lit " << fl.lit_area << " + shadowed "
          << fl.shadow_area << " != area " << fl.area << "\n";
    if (!(fl.lit_fraction >= 0.0 && fl.lit_fraction <= 1.0))
      out << describe(scene, fl.face_id, fl.light_id) << ": lit fraction " << fl.lit_fraction << " outside [0, 1]\n";
    if (with_fragments && fl.area > 0) {
      const auto it = cells.find({fl.face_id, fl.light_id});
      const double all = it == cells.end() ? 0.0 : it->second.first;
      const double lit = it == cells.end() ? 0.0 : it->second.second;
      const double tol = 1e-12 * (1.0 + fl.area) + fl.lit_area_error_bound;
      if (std::abs(all + fl.dropped_area - fl.area) > tol)
        out << describe(scene, fl.face_id, fl.light_id) << ": cells " << all << " + dropped " << fl.dropped_area
            << " != area " << fl.area << "\n";
      // An extended light's lit cells are its fully lit and penumbra cells; lit_area is that of
      // the light's centre (docs/area-lights.md).
      const bool extended = fl.light_id < scene.lights.size() && scene.lights[fl.light_id].is_extended();
      const double lit_expected = extended ? fl.fully_lit_area + fl.penumbra_area : fl.lit_area;
      if (std::abs(lit - lit_expected) > tol + fl.dropped_area)
        out << describe(scene, fl.face_id, fl.light_id) << ": lit cells " << lit << " != lit area " << lit_expected
            << "\n";
    }
    if (fl.light_id < scene.lights.size() && scene.lights[fl.light_id].is_extended() &&
        std::abs(fl.fully_lit_area + fl.penumbra_area + fl.umbra_area - fl.area) > 1e-12 * (1.0 + fl.area))
      out << describe(scene, fl.face_id, fl.light_id) << ": fully lit " << fl.fully_lit_area << " + penumbra "
          << fl.penumbra_area << " + umbra " << fl.umbra_area << " != area " << fl.area << "\n";
  }
  const std::string message = out.str();
  return {message.empty(), message.empty() ? message : "lit and shadowed parts do not partition the faces:\n" + message};
}

Verdict check_lit_claims(const Scene& scene, const ShadowResult& result, std::uint64_t seed, int points_per_fragment) {
  std::mt19937_64 rng(seed);
  std::ostringstream out;
  std::size_t checked = 0, wrong = 0;
  const ExactOracle oracle(scene);
  for (const Fragment& f : result.fragments) {
    if (f.polygon.size() < 3) continue;
    // Away from the cell's boundary by more than its vertices' rounding (half an ulp of the
    // largest coordinate), so that the exact cell holds the point too.
    double largest = 0;
    for (const glm::dvec3& v : f.polygon) largest = std::max({largest, std::abs(v.x), std::abs(v.y), std::abs(v.z)});
    const double margin = 1e-7 * diameter(f.polygon) + 16 * std::numeric_limits<double>::epsilon() * largest;
    for (const glm::dvec3& p : sample_polygon(f.polygon, static_cast<std::size_t>(std::max(points_per_fragment, 0)), margin, rng)) {
      ++checked;
      const bool lit = oracle.is_lit_on_face(f.face_id, p, f.light_id);
      if (lit != f.lit && ++wrong <= 5)
        out << describe(scene, f.face_id, f.light_id) << " fragment " << f.fragment_id << " says "
            << (f.lit ? "lit" : "shadowed") << " but the exact query at (" << p.x << ", " << p.y << ", " << p.z
            << ") says " << (lit ? "lit" : "shadowed") << "\n";
    }
  }
  if (checked == 0 && !result.fragments.empty())
    return {false, "no point could be sampled inside any fragment: nothing was checked"};
  if (wrong == 0) return {true, {}};
  std::ostringstream head;
  head.precision(17);
  head << wrong << " of " << checked << " sampled points (seed " << seed << ") disagree with their fragment:\n";
  return {false, head.str() + out.str()};
}

Scene transformed(const Scene& scene, const Similarity& s) {
  const double scale = std::ldexp(1.0, s.scale_exponent);
  auto move = [&](const glm::dvec3& p) {
    return scale * quarter_turns(p, s.quarter_turns_x, s.quarter_turns_y, s.quarter_turns_z) + s.translation;
  };
  auto turn = [&](const glm::dvec3& d) { return quarter_turns(d, s.quarter_turns_x, s.quarter_turns_y, s.quarter_turns_z); };
  Scene out = scene;
  for (Face& f : out.faces)
    for (glm::dvec3& v : f.vertices) v = move(v);
  for (Light& l : out.lights) {
    l.to_light = turn(l.to_light);
    l.position = move(l.position);
  }
  for (Plane& p : out.planes) {
    p.point = move(p.point);
    p.normal = turn(p.normal);
    p.window *= scale;
  }
  return out;
}

Verdict check_invariance(const Scene& scene, const Similarity& s, double tolerance,
                         const std::function<ShadowResult(const Scene&)>& compute) {
  const auto run = compute ? compute : areas_only;
  const ShadowResult before = run(scene);
  const ShadowResult after = run(transformed(scene, s));
  std::ostringstream out;
  out.precision(17);
  double worst = 0;
  for (const FaceLighting& a : before.lighting) {
    const FaceLighting* b = after.find(a.face_id, a.light_id);
    if (!b) {
      out << describe(scene, a.face_id, a.light_id) << ": missing after the transform\n";
      worst = std::numeric_limits<double>::infinity();
      continue;
    }
    const double e = std::abs(a.lit_fraction - b->lit_fraction);
    if (e > tolerance) {
      out << describe(scene, a.face_id, a.light_id) << ": lit fraction " << a.lit_fraction << " becomes "
          << b->lit_fraction << " (difference " << e << ")\n";
      worst = std::max(worst, e);
    }
  }
  if (out.str().empty()) return {true, {}};
  std::ostringstream head;
  head.precision(17);
  head << "not invariant under quarter turns (" << s.quarter_turns_x << ", " << s.quarter_turns_y << ", "
       << s.quarter_turns_z << "), scale 2^" << s.scale_exponent << ", translation (" << s.translation.x << ", "
       << s.translation.y << ", " << s.translation.z << "): worst difference " << worst << " > tolerance "
       << tolerance << "\n";
  return {false, head.str() + out.str()};
}

Verdict check_monotone_occluder(const Scene& scene, const std::vector<std::vector<glm::dvec3>>& occluder,
                                double tolerance) {
  Scene more = scene;
  Mesh mesh;
  mesh.name = "added occluder";
  mesh.first_face = more.faces.size();
  mesh.face_count = occluder.size();
  mesh.receiver = false;
  more.meshes.push_back(mesh);
  for (const auto& polygon : occluder) {
    Face face;
    face.vertices = polygon;
    face.mesh = more.meshes.size() - 1;
    face.source = {"shadow::testing", "added occluder"};
    more.faces.push_back(face);
  }
  const ShadowResult before = areas_only(scene);
  const ShadowResult after = areas_only(more);
  std::ostringstream out;
  out.precision(17);
  for (const FaceLighting& a : before.lighting) {
    const FaceLighting* b = after.find(a.face_id, a.light_id);
    if (!b)
      out << describe(scene, a.face_id, a.light_id) << ": missing once an occluder is added\n";
    else if (b->lit_area > a.lit_area + tolerance)
      out << describe(scene, a.face_id, a.light_id) << ": lit area grows from " << a.lit_area << " to "
          << b->lit_area << " when an occluder is added\n";
  }
  const std::string message = out.str();
  return {message.empty(), message.empty() ? message : "not monotone:\n" + message};
}

std::string Comparison::report() const {
  std::ostringstream s;
  s.precision(6);
  s << (ok ? "within tolerance" : "TOLERANCE EXCEEDED") << ": " << pairs << " face-light pairs, tolerance "
    << tolerance << "\n";
  if (pairs > 0)
    s << "worst face " << worst_face << " (" << worst_label << ") light " << worst_light << ": approximate lit fraction "
      << approximate << ", exact " << exact << ", error " << error << "\n";
  s << "seed " << seed << ": the seed the scene and the method's sampling came from; rerun with it to reproduce\n";
  return s.str();
}

Comparison compare_lit_fractions(const Scene& scene, const LitFractionMethod& approximate, double tolerance,
                                 std::uint64_t seed) {
  Comparison c;
  c.tolerance = tolerance;
  c.seed = seed;
  const ShadowResult exact = areas_only(scene);
  bool first = true;
  for (const FaceLighting& fl : exact.lighting) {
    if (fl.area <= 0) continue;
    ++c.pairs;
    const double a = approximate(scene, fl.face_id, fl.light_id);
    const double e = std::isfinite(a) ? std::abs(a - fl.lit_fraction) : std::numeric_limits<double>::infinity();
    if (first || e > c.error) {
      first = false;
      c.worst_face = fl.face_id;
      c.worst_light = fl.light_id;
      c.approximate = a;
      c.exact = fl.lit_fraction;
      c.error = e;
    }
  }
  if (c.pairs > 0) c.worst_label = label(scene, c.worst_face);
  c.ok = c.error <= tolerance;
  return c;
}

}  // namespace shadow::testing
