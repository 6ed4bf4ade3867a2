// SPDX-License-Identifier: GPL-3.0-or-later
#include "exact/convex_solids.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <unordered_map>
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
  // use. A hash table instead of an ordered map: this search runs on one thread before every
  // plane shadow and engine (a map of 240,000 keys was most of its time for 10,000 boxes).
  std::vector<std::vector<int>> face_vertices(n);
  std::vector<glm::dvec3> vertex_position;
  {
    using Key = std::array<std::uint64_t, 3>;  // the coordinates' bits, -0.0 folded
    struct KeyHash {
      std::size_t operator()(const Key& k) const {
        std::uint64_t h = 0x9e3779b97f4a7c15ULL;
        for (std::uint64_t x : k) {
          h ^= x + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2);
          h *= 0xff51afd7ed558ccdULL;
          h ^= h >> 33;
        }
        return static_cast<std::size_t>(h);
      }
    };
    auto bits = [](double x) {
      x += 0.0;
      std::uint64_t b;
      std::memcpy(&b, &x, sizeof b);
      return b;
    };
    std::unordered_map<Key, int, KeyHash> vertex_id;
    std::size_t corners = 0;
    for (std::size_t f = 0; f < n; ++f) corners += scene.faces[f].vertices.size();
    vertex_id.reserve(corners);
    for (std::size_t f = 0; f < n; ++f) {
      if (prep[f].degenerate || !prep[f].exactly_planar) continue;
      for (const glm::dvec3& v : scene.faces[f].vertices) {
        auto [it, inserted] = vertex_id.emplace(Key{bits(v.x), bits(v.y), bits(v.z)}, static_cast<int>(vertex_position.size()));
        if (inserted) vertex_position.push_back(v);
        face_vertices[f].push_back(it->second);
      }
    }
  }
  // Undirected edge -> uses (face, forward). Within one mesh only. In key order, each key's
  // uses in face order.
  struct Use {
    std::size_t mesh;
    int u, v;
    std::size_t face;
    std::size_t index;  // insertion order: a key's uses stay in face order
    bool forward;
  };
  std::vector<Use> uses_list;
  for (std::size_t f = 0; f < n; ++f) {
    const std::vector<int>& fv = face_vertices[f];
    for (std::size_t a = 0; a < fv.size(); ++a) {
      const int u = fv[a], v = fv[(a + 1) % fv.size()];
      uses_list.push_back({scene.faces[f].mesh, std::min(u, v), std::max(u, v), f, uses_list.size(), u < v});
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
