// SPDX-License-Identifier: GPL-3.0-or-later
#include "exact/convex_solids.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>
#include <map>
#include <set>
#include <tuple>

namespace shadow::exact {

std::vector<core::ConvexSolid> find_convex_solids(const Scene& scene, const std::vector<core::FacePrep>& prep,
                                            std::vector<int>& solid_of) {
  std::vector<core::ConvexSolid> solids;
  using EK = CGAL::Exact_predicates_inexact_constructions_kernel;
  const std::size_t n = scene.faces.size();
  solid_of.assign(n, -1);
  // Vertex ids by exact coordinates (+0.0 folds -0.0 into 0.0).
  std::map<std::array<double, 3>, int> vertex_id;
  std::vector<std::vector<int>> face_vertices(n);
  std::vector<glm::dvec3> vertex_position;
  for (std::size_t f = 0; f < n; ++f) {
    if (prep[f].degenerate || !prep[f].exactly_planar) continue;
    for (const glm::dvec3& v : scene.faces[f].vertices) {
      const std::array<double, 3> key{v.x + 0.0, v.y + 0.0, v.z + 0.0};
      auto [it, inserted] = vertex_id.emplace(key, static_cast<int>(vertex_position.size()));
      if (inserted) vertex_position.push_back(v);
      face_vertices[f].push_back(it->second);
    }
  }
  // Undirected edge -> uses (face, forward). Within one mesh only.
  struct Use {
    std::size_t face;
    bool forward;
  };
  std::map<std::tuple<std::size_t, int, int>, std::vector<Use>> edge_uses;
  for (std::size_t f = 0; f < n; ++f) {
    const std::vector<int>& fv = face_vertices[f];
    for (std::size_t a = 0; a < fv.size(); ++a) {
      const int u = fv[a], v = fv[(a + 1) % fv.size()];
      edge_uses[{scene.faces[f].mesh, std::min(u, v), std::max(u, v)}].push_back({f, u < v});
    }
  }
  std::vector<std::size_t> parent(n);
  for (std::size_t f = 0; f < n; ++f) parent[f] = f;
  auto find = [&](std::size_t f) {
    while (parent[f] != f) f = parent[f] = parent[parent[f]];
    return f;
  };
  std::vector<bool> open(n, false);  // touches an edge that is not shared exactly twice, oppositely
  for (const auto& [edge, uses] : edge_uses) {
    const bool manifold = uses.size() == 2 && uses[0].forward != uses[1].forward;
    if (manifold) {
      parent[find(uses[0].face)] = find(uses[1].face);
    } else {
      for (const Use& u : uses) open[u.face] = true;
    }
  }
  std::map<std::size_t, std::vector<std::size_t>> components;
  for (std::size_t f = 0; f < n; ++f)
    if (!face_vertices[f].empty()) components[find(f)].push_back(f);
  for (const auto& [root, faces] : components) {
    if (faces.size() < 4) continue;
    if (std::any_of(faces.begin(), faces.end(), [&](std::size_t f) { return open[f]; })) continue;
    std::map<int, int> local;
    core::ConvexSolid solid;
    for (std::size_t f : faces)
      for (int v : face_vertices[f])
        if (local.emplace(v, static_cast<int>(solid.vertices.size())).second)
          solid.vertices.push_back(vertex_position[v]);
    bool convex = true;
    for (std::size_t f : faces) {
      const std::vector<glm::dvec3>& fv = scene.faces[f].vertices;
      const core::FacePrep& fp = prep[f];
      auto p3 = [](const glm::dvec3& v) { return EK::Point_3(v.x, v.y, v.z); };
      const EK::Point_3 c0 = p3(fv[fp.corner[1]]), c1 = p3(fv[fp.corner[2]]), c2 = p3(fv[fp.corner[0]]);
      const CGAL::Orientation front = fp.flipped ? CGAL::NEGATIVE : CGAL::POSITIVE;
      for (const glm::dvec3& v : solid.vertices)
        if (CGAL::orientation(c0, c1, c2, p3(v)) == front) {
          convex = false;
          break;
        }
      if (!convex) break;
    }
    if (!convex) continue;
    std::set<std::pair<int, int>> edges;
    for (std::size_t f : faces) {
      const std::vector<int>& fv = face_vertices[f];
      for (std::size_t a = 0; a < fv.size(); ++a) {
        const int u = local[fv[a]], v = local[fv[(a + 1) % fv.size()]];
        edges.emplace(std::min(u, v), std::max(u, v));
      }
    }
    for (const auto& [u, v] : edges) solid.edges.push_back({u, v});
    for (std::size_t f : faces) solid_of[f] = static_cast<int>(solids.size());
    solids.push_back(std::move(solid));
  }
  return solids;
}

}  // namespace shadow::exact
