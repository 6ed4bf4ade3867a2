// SPDX-License-Identifier: GPL-3.0-or-later
#include "exact/convex_solids.hpp"

#include "runtime/parallel.hpp"
#include "geometry/point_hash.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_2_algorithms.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Polygon_mesh_processing/triangulate_faces.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/Euler_operations.h>

#include <algorithm>
#include <climits>
#include <cstdint>
#include <unordered_map>
#include <map>
#include <set>
#include <tuple>
#include <vector>

namespace shadow::exact {
namespace {

using geometry::PointKey;  // a vertex's coordinates' bits, -0.0 folded (geometry/point_hash.hpp)

/// One use of an undirected edge {u, v} (u < v, vertex ids) by a face; kept in a bucket per u.
struct EdgeUse {
  int v;
  int face;
  int mesh;      // the face's (kept here: looking it up in the faces costs a cache miss)
  bool forward;  // the face runs it from u to v
};

/// Stable sort by v: insertion sort for the usual few uses of a vertex (no buffer to allocate).
void sort_by_v(EdgeUse* begin, EdgeUse* end) {
  if (end - begin > 32) {
    std::stable_sort(begin, end, [](const EdgeUse& x, const EdgeUse& y) { return x.v < y.v; });
    return;
  }
  for (EdgeUse* i = begin + 1; i < end; ++i) {
    const EdgeUse e = *i;
    EdgeUse* j = i;
    for (; j != begin && (j - 1)->v > e.v; --j) *j = *(j - 1);
    *j = e;
  }
}

/// Whether a face takes part in the search: exactly planar, not degenerate.
bool takes_part(const core::FacePrep& p) { return !p.degenerate && p.exactly_planar; }

}  // namespace

void number_vertices(const Scene& scene, const std::vector<core::FacePrep>& prep,
                     runtime::UninitVector<int>& corner_vertex, runtime::UninitVector<glm::dvec3>& vertex_position,
                     unsigned threads) {
  const std::size_t n = scene.faces.size();
  const std::size_t corners = corner_vertex.size();
  vertex_position.clear();
  threads = std::max(1u, runtime::resolve_threads(threads));
  if (threads == 1 || corners < kParallelNumberingCorners) {
    std::vector<PointKey> keys;
    std::size_t size = 16;
    while (size < 2 * corners) size *= 2;
    const std::size_t mask = size - 1;
    std::vector<int> table(size, -1);
    std::size_t c = 0;
    for (std::size_t f = 0; f < n; ++f) {
      if (!takes_part(prep[f])) continue;
      for (const glm::dvec3& v : scene.faces[f].vertices) {
        const PointKey key = geometry::point_key(v);
        std::size_t h = static_cast<std::size_t>(geometry::point_key_hash(key)) & mask;
        while (table[h] >= 0 && keys[static_cast<std::size_t>(table[h])] != key) h = (h + 1) & mask;
        if (table[h] < 0) {
          table[h] = static_cast<int>(keys.size());
          keys.push_back(key);
          vertex_position.push_back(v);
        }
        corner_vertex[c++] = table[h];
      }
    }
    return;
  }
  // On every thread, the same ids: each corner's position and hash (by blocks of faces); the
  // corners in shards by hash, each shard in corner order; per shard, each corner's first corner
  // with its coordinates; the first corners numbered in corner order (a prefix sum), which is
  // the order of first use.
  constexpr std::size_t kFaceBlock = 4096;
  std::vector<std::size_t> face_corner(n + 1, 0);
  for (std::size_t f = 0; f < n; ++f)
    face_corner[f + 1] = face_corner[f] + (takes_part(prep[f]) ? scene.faces[f].vertices.size() : 0);
  // The arrays by corner are written in full by the parallel loops (UninitVector: their pages
  // first touched there, not zeroed here beforehand).
  runtime::UninitVector<glm::dvec3> position(corners);
  runtime::UninitVector<std::uint64_t> hash(corners);
  runtime::parallel_for_blocks(n, kFaceBlock, threads, [&](unsigned, std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t f = begin; f < end; ++f) {
      if (!takes_part(prep[f])) continue;
      std::size_t c = face_corner[f];
      for (const glm::dvec3& v : scene.faces[f].vertices) {
        position[c] = v;
        hash[c++] = geometry::point_key_hash(geometry::point_key(v));
      }
    }
  });
  constexpr unsigned kShardBits = 8;
  constexpr std::size_t kShards = std::size_t{1} << kShardBits;
  constexpr std::size_t kCornerBlock = 1 << 16;
  const std::size_t blocks = (corners + kCornerBlock - 1) / kCornerBlock;
  auto shard_of = [&](std::size_t c) { return static_cast<std::size_t>(hash[c] >> (64 - kShardBits)); };
  // count[b * kShards + s]: block b's corners in shard s; then their place in the shard lists.
  std::vector<std::size_t> count(blocks * kShards, 0);
  runtime::parallel_for_blocks(corners, kCornerBlock, threads, [&](unsigned, std::size_t b, std::size_t begin, std::size_t end) {
    for (std::size_t c = begin; c < end; ++c) ++count[b * kShards + shard_of(c)];
  });
  std::vector<std::size_t> shard_start(kShards + 1, 0);
  {
    std::size_t at = 0;
    for (std::size_t s = 0; s < kShards; ++s) {
      shard_start[s] = at;
      for (std::size_t b = 0; b < blocks; ++b) {
        const std::size_t k = count[b * kShards + s];
        count[b * kShards + s] = at;
        at += k;
      }
    }
    shard_start[kShards] = at;
  }
  runtime::UninitVector<std::uint32_t> in_shard(corners);
  runtime::parallel_for_blocks(corners, kCornerBlock, threads, [&](unsigned, std::size_t b, std::size_t begin, std::size_t end) {
    for (std::size_t c = begin; c < end; ++c) in_shard[count[b * kShards + shard_of(c)]++] = static_cast<std::uint32_t>(c);
  });
  // first[c]: the first corner with c's coordinates.
  runtime::UninitVector<std::uint32_t> first(corners);
  runtime::parallel_for(kShards, threads, [&](unsigned, std::size_t s) {
    const std::size_t begin = shard_start[s], end = shard_start[s + 1];
    std::size_t size = 16;
    while (size < 2 * (end - begin)) size *= 2;
    const std::size_t mask = size - 1;
    std::vector<std::uint32_t> table(size, UINT32_MAX);  // a first corner, or empty
    for (std::size_t i = begin; i < end; ++i) {
      const std::uint32_t c = in_shard[i];
      const PointKey key = geometry::point_key(position[c]);
      std::size_t h = static_cast<std::size_t>(hash[c]) & mask;
      while (table[h] != UINT32_MAX && geometry::point_key(position[table[h]]) != key) h = (h + 1) & mask;
      if (table[h] == UINT32_MAX) table[h] = c;
      first[c] = table[h];
    }
  });
  // Ids of first corners in corner order: per block, then the blocks' offsets.
  std::vector<std::size_t> firsts(blocks + 1, 0);
  runtime::parallel_for_blocks(corners, kCornerBlock, threads, [&](unsigned, std::size_t b, std::size_t begin, std::size_t end) {
    std::size_t k = 0;
    for (std::size_t c = begin; c < end; ++c) k += first[c] == c ? 1 : 0;
    firsts[b + 1] = k;
  });
  for (std::size_t b = 0; b < blocks; ++b) firsts[b + 1] += firsts[b];
  vertex_position.resize(firsts[blocks]);
  runtime::parallel_for_blocks(corners, kCornerBlock, threads, [&](unsigned, std::size_t b, std::size_t begin, std::size_t end) {
    std::size_t id = firsts[b];
    for (std::size_t c = begin; c < end; ++c)
      if (first[c] == c) {
        vertex_position[id] = position[c];
        corner_vertex[c] = static_cast<int>(id++);
      }
  });
  // Every other corner takes its first corner's id (set above, in any block).
  runtime::parallel_for_blocks(corners, kCornerBlock, threads, [&](unsigned, std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t c = begin; c < end; ++c)
      if (first[c] != c) corner_vertex[c] = corner_vertex[first[c]];
  });
}

namespace {

/// Whether a part (its faces, `faces`) bounds a convex solid: every vertex of the part on or
/// behind every face's plane (exact orientation). Then `solid` gets its vertices and edges;
/// else it is left empty. `local` (vertex id -> local number, -1 for none) numbers the part's
/// vertices, listed in `ids` for the caller to reset.
template <class FaceVertex, class FaceSize>
bool test_part(const Scene& scene, const std::vector<core::FacePrep>& prep, const std::size_t* faces,
               std::size_t face_count, const FaceVertex& face_vertex, const FaceSize& face_size,
               const runtime::UninitVector<glm::dvec3>& vertex_position, std::vector<int>& local, std::vector<int>& ids,
               std::vector<std::pair<int, int>>& edges, core::ConvexSolid& solid) {
  using EK = CGAL::Exact_predicates_inexact_constructions_kernel;
  ids.clear();
  for (std::size_t i = 0; i < face_count; ++i)
    for (std::size_t a = 0, m = face_size(faces[i]); a < m; ++a) {
      const int v = face_vertex(faces[i], a);
      if (local[static_cast<std::size_t>(v)] < 0) {
        local[static_cast<std::size_t>(v)] = static_cast<int>(ids.size());
        ids.push_back(v);
        solid.vertices.push_back(vertex_position[static_cast<std::size_t>(v)]);
      }
    }
  bool convex = true;
  auto p3 = [](const glm::dvec3& v) { return EK::Point_3(v.x, v.y, v.z); };
  for (std::size_t i = 0; i < face_count && convex; ++i) {
    const std::vector<glm::dvec3>& fv = scene.faces[faces[i]].vertices;
    const core::FacePrep& fp = prep[faces[i]];
    const EK::Point_3 c0 = p3(fv[fp.corner[1]]), c1 = p3(fv[fp.corner[2]]), c2 = p3(fv[fp.corner[0]]);
    const CGAL::Orientation front = fp.flipped ? CGAL::NEGATIVE : CGAL::POSITIVE;
    for (const glm::dvec3& v : solid.vertices)
      if (CGAL::orientation(c0, c1, c2, p3(v)) == front) {
        convex = false;
        break;
      }
  }
  if (convex) {
    edges.clear();
    for (std::size_t i = 0; i < face_count; ++i)
      for (std::size_t a = 0, m = face_size(faces[i]); a < m; ++a) {
        const int u = local[static_cast<std::size_t>(face_vertex(faces[i], a))];
        const int v = local[static_cast<std::size_t>(face_vertex(faces[i], (a + 1) % m))];
        edges.emplace_back(std::min(u, v), std::max(u, v));
      }
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    solid.edges.reserve(edges.size());
    for (const auto& [u, v] : edges) solid.edges.push_back({u, v});
  } else {
    solid = core::ConvexSolid{};
  }
  return convex;
}

/// Whether a part that is not convex, its faces joined along edges used twice in opposite
/// directions, bounds a solid, and which way its faces' vertex order turns: +1 outward, -1
/// inward, 0 when it is not shown to be a solid. Its border (edges used once), if any, must be
/// loops each in one horizontal plane (a building's walls and roof without its floor): each is
/// closed by a cap, a face that only a light below its plane could see from outside; such a
/// part gives +2 or -2, valid under a light above every cap, and 0 when some cap faces up from
/// the solid. Shown with CGAL's exact predicates on a surface mesh of the part and its caps:
/// every face added and a valid mesh (a manifold surface: no pinched vertex), closed,
/// triangulated where a face is not a triangle, no two triangles meeting but at their shared
/// edges and vertices (a degenerate triangle counts as meeting itself; the triangulation
/// projects with an approximate normal, and a fold it might make is such a meeting), and then
/// oriented. An embedded closed surface bounds its inside once, so a ray from any point outside
/// or inside it that crosses it going in leaves it again before the light: why the faces
/// turned away from the light may be dropped (and the caps, turned away from a light above
/// them, were never there to cast).
template <class FaceVertex, class FaceSize>
int closed_part_orientation(const std::size_t* faces, std::size_t face_count, const FaceVertex& face_vertex,
                            const FaceSize& face_size, const runtime::UninitVector<glm::dvec3>& vertex_position,
                            std::vector<int>& local, std::vector<int>& ids) {
  using EK = CGAL::Exact_predicates_inexact_constructions_kernel;
  using Mesh = CGAL::Surface_mesh<EK::Point_3>;
  namespace PMP = CGAL::Polygon_mesh_processing;
  Mesh mesh;
  ids.clear();
  int result = 0;
  try {
    std::vector<Mesh::Vertex_index> loop;
    bool added = true;
    bool triangles = true;
    for (std::size_t i = 0; i < face_count && added; ++i) {
      loop.clear();
      const std::size_t m = face_size(faces[i]);
      triangles = triangles && m == 3;
      for (std::size_t a = 0; a < m; ++a) {
        const int v = face_vertex(faces[i], a);
        int& l = local[static_cast<std::size_t>(v)];
        if (l < 0) {
          const glm::dvec3& p = vertex_position[static_cast<std::size_t>(v)];
          l = static_cast<int>(mesh.add_vertex(EK::Point_3(p.x, p.y, p.z)));
          ids.push_back(v);
        }
        loop.push_back(Mesh::Vertex_index(static_cast<Mesh::size_type>(l)));
      }
      added = mesh.add_face(loop) != Mesh::null_face();
    }
    if (!added) return 0;
    // The caps: every border loop horizontal, filled by a face; which way each faces is read
    // after the orientation is known (a cap's vertices run clockwise seen from above when
    // its outward side faces down).
    std::vector<std::vector<EK::Point_2>> caps;
    std::vector<char> seen(mesh.number_of_halfedges(), 0);
    for (Mesh::Halfedge_index h : mesh.halfedges()) {
      if (!mesh.is_border(h) || seen[h.idx()]) continue;
      std::vector<EK::Point_2>& cap = caps.emplace_back();
      const double z = mesh.point(mesh.source(h)).z();
      Mesh::Halfedge_index g = h;
      do {
        seen[g.idx()] = 1;
        const EK::Point_3& p = mesh.point(mesh.source(g));
        if (p.z() != z) return 0;  // not horizontal
        cap.emplace_back(p.x(), p.y());
        g = mesh.next(g);
      } while (g != h);
    }
    for (Mesh::Halfedge_index h : mesh.halfedges())
      if (mesh.is_border(h)) CGAL::Euler::fill_hole(h, mesh);
    // add_face refuses an edge taken twice or a vertex already surrounded, but two fans of faces
    // meeting at one vertex (a pinch) can both be built: is_valid_polygon_mesh counts each
    // vertex's halfedges and rejects it (is_outward_oriented, which reads one fan of the highest
    // vertex, could then read the wrong one).
    if (!CGAL::is_closed(mesh) || (!(triangles && caps.empty()) && !PMP::triangulate_faces(mesh)) ||
        !CGAL::is_valid_polygon_mesh(mesh) || PMP::does_self_intersect(mesh))
      return 0;
    const int orientation = PMP::is_outward_oriented(mesh) ? 1 : -1;
    // A cap's vertex order (its border halfedges' sources) is its face's; outward it must face
    // down: clockwise from above when the order is outward, counter-clockwise when inward.
    for (const std::vector<EK::Point_2>& cap : caps) {
      const CGAL::Orientation turn = CGAL::orientation_2(cap.begin(), cap.end(), EK());
      if (turn != (orientation > 0 ? CGAL::CLOCKWISE : CGAL::COUNTERCLOCKWISE)) return 0;
    }
    result = caps.empty() ? orientation : 2 * orientation;
  } catch (...) {  // a precondition CGAL checks on a surface it cannot take: not shown
    result = 0;
  }
  return result;
}

}  // namespace

// The same search as find_convex_solids_reference, step for step, with the same result:
// - vertex ids in order of first use (an open-addressing table of ids instead of a node map);
// - the edge uses in (u, v, face order) order: a counting sort by u and a stable sort by v
//   within each u (small buckets) instead of one sort of every use by (mesh, u, v, index);
//   uses of one edge by several meshes are split by mesh, keeping face order. The reference
//   sorts mesh first, but a union joins faces of one mesh only, and the union-find root of a
//   part (which orders the solids) depends only on the order of that part's own unions, which
//   is (u, v) order in both;
// - the parts listed in flat arrays, and each candidate part (at least four faces, every edge
//   shared) tested and assembled on its own thread, with a scratch array per thread for its
//   local vertex numbers and a sorted vector for its edges (the reference: a map and a set).
std::vector<core::ConvexSolid> find_convex_solids(const Scene& scene, const std::vector<core::FacePrep>& prep,
                                            std::vector<int>& solid_of, unsigned threads,
                                            std::vector<signed char>* closed_outward) {
  const std::size_t n = scene.faces.size();
  if (closed_outward) closed_outward->assign(n, 0);
  std::vector<std::size_t> corner_start(n + 1, 0);
  std::size_t max_mesh = 0;
  for (std::size_t f = 0; f < n; ++f) {
    corner_start[f + 1] = corner_start[f] + (takes_part(prep[f]) ? scene.faces[f].vertices.size() : 0);
    max_mesh = std::max(max_mesh, scene.faces[f].mesh);
  }
  const std::size_t corners = corner_start[n];
  if (corners >= static_cast<std::size_t>(INT_MAX) / 4 || n >= static_cast<std::size_t>(INT_MAX) ||
      max_mesh >= static_cast<std::size_t>(INT_MAX))
    return find_convex_solids_reference(scene, prep, solid_of);  // beyond int ids
  solid_of.assign(n, -1);

  // Vertex ids by exact coordinates, numbered in order of first use.
  runtime::UninitVector<int> corner_vertex(corners);  // (every corner's id written by number_vertices)
  runtime::UninitVector<glm::dvec3> vertex_position;
  number_vertices(scene, prep, corner_vertex, vertex_position, threads);
  const std::size_t vertex_count = vertex_position.size();
  auto face_vertex = [&](std::size_t f, std::size_t a) { return corner_vertex[corner_start[f] + a]; };
  auto face_size = [&](std::size_t f) { return corner_start[f + 1] - corner_start[f]; };

  // Edge uses bucketed by their lower vertex id, in face order within each bucket.
  std::vector<std::size_t> bucket(vertex_count + 1, 0);
  for (std::size_t f = 0; f < n; ++f)
    for (std::size_t a = 0, m = face_size(f); a < m; ++a)
      ++bucket[static_cast<std::size_t>(std::min(face_vertex(f, a), face_vertex(f, (a + 1) % m))) + 1];
  for (std::size_t u = 0; u < vertex_count; ++u) bucket[u + 1] += bucket[u];
  std::vector<EdgeUse> uses(corners);
  {
    std::vector<std::size_t> fill(bucket.begin(), bucket.end() - 1);
    for (std::size_t f = 0; f < n; ++f)
      for (std::size_t a = 0, m = face_size(f); a < m; ++a) {
        const int u = face_vertex(f, a), v = face_vertex(f, (a + 1) % m);
        uses[fill[static_cast<std::size_t>(std::min(u, v))]++] = {std::max(u, v), static_cast<int>(f),
                                                                  static_cast<int>(scene.faces[f].mesh), u < v};
      }
  }
  std::vector<std::size_t> parent(n);
  for (std::size_t f = 0; f < n; ++f) parent[f] = f;
  auto find = [&](std::size_t f) {
    while (parent[f] != f) f = parent[f] = parent[parent[f]];
    return f;
  };
  std::vector<char> open(n, 0);  // touches an edge that is not shared exactly twice, oppositely (bits 1, 2: below)
  auto edge_group = [&](std::size_t u, const EdgeUse* first, const EdgeUse* last) {
    if (last - first == 2 && first[0].forward != first[1].forward) {
      parent[find(static_cast<std::size_t>(first[0].face))] = find(static_cast<std::size_t>(first[1].face));
    } else {
      // 1: a horizontal border edge (used once), as a cap's; 2: any other (a sloping border: no mesh built).
      const char kind = last - first == 1 && vertex_position[u].z == vertex_position[static_cast<std::size_t>(first->v)].z ? 1 : 2;
      for (const EdgeUse* e = first; e != last; ++e) open[static_cast<std::size_t>(e->face)] |= kind;
    }
  };
  auto mesh_of = [](const EdgeUse& e) { return e.mesh; };
  std::vector<EdgeUse> split;
  for (std::size_t u = 0; u < vertex_count; ++u) {
    EdgeUse* const begin = uses.data() + bucket[u];
    EdgeUse* const end = uses.data() + bucket[u + 1];
    sort_by_v(begin, end);
    for (EdgeUse* a = begin; a != end;) {
      EdgeUse* b = a + 1;
      bool one_mesh = true;
      while (b != end && b->v == a->v) {
        one_mesh = one_mesh && mesh_of(*b) == mesh_of(*a);
        ++b;
      }
      if (one_mesh) {
        edge_group(u, a, b);
      } else {  // the edge in several meshes: one group per mesh, each in face order
        split.assign(a, b);
        std::stable_sort(split.begin(), split.end(),
                         [&](const EdgeUse& x, const EdgeUse& y) { return mesh_of(x) < mesh_of(y); });
        for (std::size_t s = 0; s < split.size();) {
          std::size_t t = s + 1;
          while (t < split.size() && mesh_of(split[t]) == mesh_of(split[s])) ++t;
          edge_group(u, split.data() + s, split.data() + t);
          s = t;
        }
      }
      a = b;
    }
  }

  // The parts: faces by root, in face order, roots in increasing order.
  std::vector<std::size_t> part_start(n + 1, 0);
  for (std::size_t f = 0; f < n; ++f)
    if (face_size(f) > 0) ++part_start[find(f) + 1];
  for (std::size_t r = 0; r < n; ++r) part_start[r + 1] += part_start[r];
  std::vector<std::size_t> part_faces(part_start[n]);
  std::vector<char> part_open(n, 0);
  {
    std::vector<std::size_t> fill(part_start.begin(), part_start.end() - 1);
    for (std::size_t f = 0; f < n; ++f)
      if (face_size(f) > 0) {
        const std::size_t r = find(f);
        part_faces[fill[r]++] = f;
        part_open[r] |= open[f];
      }
  }
  std::vector<std::size_t> candidates;
  for (std::size_t r = 0; r < n; ++r)
    if (part_start[r + 1] - part_start[r] >= 4 && (!part_open[r] || (closed_outward && part_open[r] == 1)))
      candidates.push_back(r);  // closed, or (for closed_outward alone) open along a border only

  std::vector<core::ConvexSolid> found(candidates.size());
  std::vector<char> convex_part(candidates.size(), 0);
  std::vector<signed char> orientation(candidates.size(), 0);  // closed parts that are not convex
  const unsigned workers = std::max(1u, runtime::resolve_threads(threads));
  std::vector<std::vector<int>> local_of(workers);  // per worker: vertex id -> local number, or -1
  constexpr std::size_t kChunk = 64;
  runtime::parallel_for_blocks(candidates.size(), kChunk, workers, [&](unsigned worker, std::size_t, std::size_t begin,
                                                                     std::size_t end) {
    std::vector<int>& local = local_of[worker];
    if (local.empty()) local.assign(vertex_count, -1);
    std::vector<int> ids;  // the part's vertex ids, in order of first use
    std::vector<std::pair<int, int>> edges;
    for (std::size_t item = begin; item < end; ++item) {
      const std::size_t r = candidates[item];
      const std::size_t* const faces = part_faces.data() + part_start[r];
      const std::size_t face_count = part_start[r + 1] - part_start[r];
      core::ConvexSolid& solid = found[item];
      if (part_open[r] == 0) {  // closed: convex? (a part with a border is never a convex solid)
        convex_part[item] = test_part(scene, prep, faces, face_count, face_vertex, face_size, vertex_position, local,
                                      ids, edges, solid) ? 1 : 0;
        for (int v : ids) local[static_cast<std::size_t>(v)] = -1;
      }
      if (convex_part[item] || !closed_outward) continue;
      orientation[item] = static_cast<signed char>(
          closed_part_orientation(faces, face_count, face_vertex, face_size, vertex_position, local, ids));
      for (int v : ids) local[static_cast<std::size_t>(v)] = -1;
    }
  });
  std::vector<core::ConvexSolid> solids;
  for (std::size_t item = 0; item < candidates.size(); ++item) {
    if (!convex_part[item]) {
      if (orientation[item] != 0)
        for (std::size_t i = part_start[candidates[item]]; i < part_start[candidates[item] + 1]; ++i)
          (*closed_outward)[part_faces[i]] = orientation[item];
      continue;
    }
    const std::size_t r = candidates[item];
    for (std::size_t i = part_start[r]; i < part_start[r + 1]; ++i) solid_of[part_faces[i]] = static_cast<int>(solids.size());
    solids.push_back(std::move(found[item]));
  }
  return solids;
}


std::vector<core::ConvexSolid> find_convex_solids_reference(const Scene& scene, const std::vector<core::FacePrep>& prep,
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
    std::unordered_map<PointKey, int, geometry::PointKeyHash> vertex_id;
    std::size_t corners = 0;
    for (std::size_t f = 0; f < n; ++f) corners += scene.faces[f].vertices.size();
    vertex_id.reserve(corners);
    for (std::size_t f = 0; f < n; ++f) {
      if (prep[f].degenerate || !prep[f].exactly_planar) continue;
      for (const glm::dvec3& v : scene.faces[f].vertices) {
        auto [it, inserted] = vertex_id.emplace(geometry::point_key(v), static_cast<int>(vertex_position.size()));
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
