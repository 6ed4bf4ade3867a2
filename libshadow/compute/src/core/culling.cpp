// SPDX-License-Identifier: GPL-3.0-or-later
#include "core/culling.hpp"

#include "geometry/bounding_box.hpp"
#include "geometry/newell_normal.hpp"
#include "runtime/parallel.hpp"

#include <glm/common.hpp>

#include <algorithm>
#include <vector>

namespace shadow::core {

SceneFrame scene_frame(const Scene& scene, unsigned threads) {
  if (scene.faces.empty()) return {};
  constexpr std::size_t kBlock = 16384;
  const std::size_t n = scene.faces.size();
  if (threads <= 1 || n <= kBlock) {
    const geometry::BoundingBox box = geometry::faces_bounding_box(scene.faces);
    return {box.centre(), std::max(box.diagonal(), 1e-300)};
  }
  // Each block's box, then the blocks' in order: min and max keep the first of equal values
  // (+0.0 or -0.0), so this is the box one pass over the faces finds.
  std::vector<geometry::BoundingBox> blocks((n + kBlock - 1) / kBlock);
  runtime::parallel_for_blocks(n, kBlock, threads, [&](unsigned, std::size_t b, std::size_t begin, std::size_t end) {
    for (std::size_t f = begin; f < end; ++f)
      for (const glm::dvec3& v : scene.faces[f].vertices) blocks[b].add(v);
  });
  geometry::BoundingBox box;
  for (const geometry::BoundingBox& block : blocks)
    if (block.any) {
      box.lo = glm::min(box.lo, block.lo);
      box.hi = glm::max(box.hi, block.hi);
      box.any = true;
    }
  return {box.centre(), std::max(box.diagonal(), 1e-300)};
}

namespace {

/// Face f of `cull`, its vertices starting at `first` in cull.vertices: every field of it set (its
/// range, its unit normal with an error bound, its plane offset and, for a face that is not
/// exactly planar, its slack) and its vertices written in the local frame.
void describe_face(const Scene& scene, const std::vector<FacePrep>& prep, std::size_t f, std::size_t first,
                   CullScene& cull) {
  CullFace& cf = cull.faces[f];
  const std::vector<glm::dvec3>& vertices = scene.faces[f].vertices;
  // A degenerate face (or one whose normal is lost) keeps these: no normal, direction unknown.
  cf = CullFace{first, vertices.size(), glm::dvec3(0.0), 2.0, 0.0, 0.0};
  for (std::size_t a = 0; a < cf.count; ++a) cull.vertices[cf.first + a] = vertices[a] - cull.origin;
  // Newell's normal relative to the face's own first vertex: relative to the scene's centre a
  // small face far from it would lose its normal's direction to cancellation. `bound` sums the
  // terms' magnitudes: each component's rounding error (differences, sums, products and the
  // running sum of m terms) is under (m + 8) eps times its magnitude sum.
  glm::dvec3 n(0.0), bound(0.0);
  for (std::size_t a = 0; a < cf.count; ++a) {
    const glm::dvec3 u = vertices[a] - vertices[0];
    const glm::dvec3 v = vertices[(a + 1) % cf.count] - vertices[0];
    n += geometry::newell_term(u, v);
    const glm::dvec3 au = glm::abs(u), av = glm::abs(v);
    bound += glm::dvec3((au.y + av.y) * (au.z + av.z), (au.z + av.z) * (au.x + av.x),
                        (au.x + av.x) * (au.y + av.y));
  }
  const double len = glm::length(n);
  if (prep[f].degenerate || !(len > 0) || !std::isfinite(len)) return;
  cf.normal = n / len;
  constexpr double eps = std::numeric_limits<double>::epsilon();
  const double error = (static_cast<double>(cf.count) + 8) * eps * glm::length(bound) * (1 + 1e-9);
  // |n/|n| - n_exact/|n_exact|| <= 2 |n - n_exact| / |n_exact|, plus the division's rounding.
  cf.normal_error = std::isfinite(error) && error < 0.5 * len ? std::min(2.0, 2 * error / (len - error) + 4 * eps) : 2.0;
  glm::dvec3 centroid(0.0);
  for (std::size_t a = 0; a < cf.count; ++a) centroid += cull.vertices[cf.first + a];
  centroid /= static_cast<double>(cf.count);
  cf.offset = -glm::dot(cf.normal, centroid);
  if (!prep[f].exactly_planar) {
    // The lift moves a vertex along the chart axis k by its distance to the exact plane / |n_k|;
    // that distance is the double one plus the normal's error times the vertex's reach.
    double furthest = 0.0, reach = 0.0;
    for (std::size_t a = 0; a < cf.count; ++a) {
      const glm::dvec3& p = cull.vertices[cf.first + a];
      furthest = std::max(furthest, std::abs(glm::dot(cf.normal, p) + cf.offset));
      reach = std::max(reach, glm::length(p - centroid));
    }
    const double nk = std::abs(cf.normal[prep[f].axis]) - cf.normal_error;
    cf.slack = nk > 0 ? 2.0 * (furthest + cf.normal_error * 2 * reach) / nk + 1e-12 * cull.diameter
                      : 2.0 * cull.diameter;
  }
}

}  // namespace

std::vector<LocalBounds> face_bounds(const CullScene& scene, unsigned threads) {
  std::vector<LocalBounds> bounds(scene.faces.size());
  runtime::parallel_for_blocks(bounds.size(), 8192, threads, [&](unsigned, std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t f = begin; f < end; ++f) {
      const CullFace& cf = scene.faces[f];
      LocalBounds& b = bounds[f];
      b.slack = cf.slack;
      if (cf.count == 0) continue;
      b.lo = b.hi = scene.vertices[cf.first];
      for (std::size_t k = cf.first + 1; k < cf.first + cf.count; ++k) {
        b.lo = glm::min(b.lo, scene.vertices[k]);
        b.hi = glm::max(b.hi, scene.vertices[k]);
      }
    }
  });
  return bounds;
}

CullScene make_cull_scene(const Scene& scene, const std::vector<FacePrep>& prep, unsigned threads) {
  CullScene cull;
  const SceneFrame frame = scene_frame(scene, runtime::resolve_threads(threads == 0 ? 1 : threads));
  cull.origin = frame.centre;
  cull.diameter = frame.diagonal;
  const std::size_t n = scene.faces.size();
  // Blocks of faces as work items (one face is a few hundred nanoseconds): each block's vertex
  // count, the blocks' first vertices, then every face described (every field of it and of its
  // vertices written) on the thread of its block.
  constexpr std::size_t kBlock = 4096;
  const std::size_t blocks = (n + kBlock - 1) / kBlock;
  std::vector<std::size_t> block_first(blocks + 1, 0);
  runtime::parallel_for_blocks(n, kBlock, threads, [&](unsigned, std::size_t b, std::size_t begin, std::size_t end) {
    std::size_t count = 0;
    for (std::size_t f = begin; f < end; ++f) count += scene.faces[f].vertices.size();
    block_first[b + 1] = count;
  });
  for (std::size_t b = 0; b < blocks; ++b) block_first[b + 1] += block_first[b];
  cull.faces.resize(n);
  cull.vertices.resize(block_first[blocks]);
  runtime::parallel_for_blocks(n, kBlock, threads, [&](unsigned, std::size_t b, std::size_t begin, std::size_t end) {
    std::size_t first = block_first[b];
    for (std::size_t f = begin; f < end; ++f) {
      describe_face(scene, prep, f, first, cull);
      first += scene.faces[f].vertices.size();
    }
  });
  return cull;
}


}  // namespace shadow::core
