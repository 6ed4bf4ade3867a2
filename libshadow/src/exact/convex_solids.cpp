// SPDX-License-Identifier: GPL-3.0-or-later
#include "exact/convex_solids.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <map>
#include <set>
#include <tuple>
#include <vector>

namespace shadow::exact {

std::vector<core::ConvexSolid> find_convex_solids(const Scene& scene, const std::vector<core::FacePrep>& prep,
                                            std::vector<int>& solid_of) {
  std::vector<core::ConvexSolid> solids;
  using EK = CGAL::Exact_predicates_inexact_constructions_kernel;
  const std::size_t n = scene.faces.size();
  solid_of.assign(n, -1);
  // Vertex ids by exact coordinates (+0.0 folds -0.0 into 0.0), numbered in order of first
  // use. Sorted arrays instead of ordered maps: this search runs before every plane shadow
  // and engine, on one thread (a map of 240,000 keys was most of its time for 10,000 boxes).
  std::vector<std::vector<int>> face_vertices(n);
  std::vector<glm::dvec3> vertex_position;
  {
    struct Corner {
      std::array<double, 3> key;
      std::uint32_t use;  // position in face order
    };
    std::vector<Corner> corners;
    std::vector<std::size_t> first_use(n + 1, 0);
    std::vector<const glm::dvec3*> position_of;  // by use, as given (a first use's -0.0 stays)
    for (std::size_t f = 0; f < n; ++f) {
      first_use[f] = corners.size();
      if (prep[f].degenerate || !prep[f].exactly_planar) continue;
      for (const glm::dvec3& v : scene.faces[f].vertices) {
        corners.push_back({{v.x + 0.0, v.y + 0.0, v.z + 0.0}, static_cast<std::uint32_t>(corners.size())});
        position_of.push_back(&v);
      }
    }
    first_use[n] = corners.size();
    std::sort(corners.begin(), corners.end(), [](const Corner& a, const Corner& b) { return a.key != b.key ? a.key < b.key : a.use < b.use; });
    // Each group of equal keys: its first use names it; ids follow the first uses' order.
    std::vector<std::uint32_t> group_of(corners.size());
    std::vector<std::uint32_t> group_first;
    for (std::size_t a = 0; a < corners.size(); ++a) {
      if (a == 0 || corners[a].key != corners[a - 1].key) group_first.push_back(corners[a].use);
      group_of[corners[a].use] = static_cast<std::uint32_t>(group_first.size() - 1);
    }
    std::vector<std::uint32_t> by_first(group_first.size());
    for (std::size_t g = 0; g < by_first.size(); ++g) by_first[g] = static_cast<std::uint32_t>(g);
    std::sort(by_first.begin(), by_first.end(), [&](std::uint32_t a, std::uint32_t b) { return group_first[a] < group_first[b]; });
    std::vector<int> id_of_group(group_first.size());
    vertex_position.resize(group_first.size());
    for (std::size_t rank = 0; rank < by_first.size(); ++rank) {
      id_of_group[by_first[rank]] = static_cast<int>(rank);
      vertex_position[rank] = *position_of[group_first[by_first[rank]]];
    }
    for (std::size_t f = 0; f < n; ++f)
      for (std::size_t c = first_use[f]; c < first_use[f + 1]; ++c) face_vertices[f].push_back(id_of_group[group_of[c]]);
  }
  // Undirected edge -> uses (face, forward). Within one mesh only. In key order, each key's
  // uses in face order.
  struct Use {
    std::size_t mesh;
    int u, v;
    std::uint32_t face;
    std::uint32_t index;  // insertion order: a key's uses stay in face order
    bool forward;
  };
  std::vector<Use> uses_list;
  for (std::size_t f = 0; f < n; ++f) {
    const std::vector<int>& fv = face_vertices[f];
    for (std::size_t a = 0; a < fv.size(); ++a) {
      const int u = fv[a], v = fv[(a + 1) % fv.size()];
      uses_list.push_back({scene.faces[f].mesh, std::min(u, v), std::max(u, v), static_cast<std::uint32_t>(f),
                           static_cast<std::uint32_t>(uses_list.size()), u < v});
    }
  }
  std::sort(uses_list.begin(), uses_list.end(), [](const Use& a, const Use& b) {
    return std::tie(a.mesh, a.u, a.v, a.index) < std::tie(b.mesh, b.u, b.v, b.index);
  });
  std::vector<std::size_t> parent(n);
  for (std::size_t f = 0; f < n; ++f) parent[f] = f;
  auto find = [&](std::size_t f) {
    while (parent[f] != f) f = parent[f] = parent[parent[f]];
    return f;
  };
  std::vector<bool> open(n, false);  // touches an edge that is not shared exactly twice, oppositely
  for (std::size_t a = 0; a < uses_list.size();) {
    std::size_t b = a + 1;
    while (b < uses_list.size() && uses_list[b].mesh == uses_list[a].mesh && uses_list[b].u == uses_list[a].u &&
           uses_list[b].v == uses_list[a].v)
      ++b;
    const bool manifold = b - a == 2 && uses_list[a].forward != uses_list[a + 1].forward;
    if (manifold) {
      parent[find(uses_list[a].face)] = find(uses_list[a + 1].face);
    } else {
      for (std::size_t c = a; c < b; ++c) open[uses_list[c].face] = true;
    }
    a = b;
  }
  std::vector<std::vector<std::size_t>> component(n);  // by root, in root order below
  for (std::size_t f = 0; f < n; ++f)
    if (!face_vertices[f].empty()) component[find(f)].push_back(f);
  for (std::size_t root = 0; root < n; ++root) {
    const std::vector<std::size_t>& faces = component[root];
    if (faces.empty()) continue;
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
