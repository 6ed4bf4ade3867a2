// SPDX-License-Identifier: GPL-3.0-or-later
// The orientation check of a scene's meshes (validation/mesh_orientation.hpp): closed parts found by
// shared edges (in parallel for large meshes), inward or inconsistent ones warned about, or
// turned outward on request.
#include "validation/mesh_orientation.hpp"

#include "runtime/parallel.hpp"
#include "runtime/uninit_vector.hpp"
#include "geometry/point_hash.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace shadow::validation {
namespace {

/// A mesh's edges, keyed by their two end points (exact coordinates), lowest first.
struct EdgeKey {
  glm::dvec3 a, b;
  bool operator<(const EdgeKey& o) const {
    auto less = [](const glm::dvec3& p, const glm::dvec3& q) {
      return p.x != q.x ? p.x < q.x : p.y != q.y ? p.y < q.y : p.z < q.z;
    };
    if (a != o.a) return less(a, o.a);
    return less(b, o.b);
  }
};

/// "faces 3 (\"wall\"), 4, 7 (\"roof\") and 12 more": the first few faces of a part by id and name.
std::string list_faces(const Scene& scene, const std::vector<std::size_t>& ids) {
  constexpr std::size_t kShown = 5;
  std::string text = ids.size() == 1 ? "face " : "faces ";
  for (std::size_t i = 0; i < ids.size() && i < kShown; ++i) {
    if (i > 0) text += ", ";
    text += std::to_string(ids[i]);
    const Face& face = scene.faces[ids[i]];
    if (!face.name.empty()) text += " (\"" + face.name + "\")";
  }
  if (ids.size() > kShown) text += " and " + std::to_string(ids.size() - kShown) + " more";
  const std::string at = scene.faces[ids[0]].source.to_string();
  if (!at.empty()) text += "; the first at " + at;
  return text;
}

/// An edge use of a mesh: the edge's key (equal for the uses of one edge), the face (index into
/// the mesh's list of faces) and whether it runs the edge forward (from its lower end point, in
/// whatever order the keys were made with, to the higher).
struct EdgeUse {
  std::uint64_t key;
  std::uint32_t face;
  bool forward;
};

/// Meshes of this many faces or more are checked on every thread (grouped_edge_uses, parts in
/// parallel); smaller ones many at once, one thread each, with the coordinate sort.
constexpr std::size_t kLargeMesh = 4096;

/// 256 shards, chosen by a hash's top byte: the parallel grouping's unit of work (a fixed
/// number, so that the work does not depend on the thread count).
constexpr std::size_t kShards = 256;

/// The items make(i) for i in [0, n), grouped by shard_of(i) < kShards and in index order within
/// a shard (a counting scatter, in parallel over blocks of indices): shard s is
/// out[start[s], start[s + 1]). Reading the inputs in order and writing each shard's items one
/// after the other keeps the memory traffic sequential.
template <class T, class ShardOf, class Make>
void scatter_by_shard(std::size_t n, unsigned threads, const ShardOf& shard_of, const Make& make,
                      runtime::UninitVector<T>& out, std::vector<std::size_t>& start) {
  constexpr std::size_t kBlock = std::size_t{1} << 16;
  const std::size_t blocks = (n + kBlock - 1) / kBlock;
  std::vector<std::size_t> at(blocks * kShards, 0);
  runtime::parallel_for_blocks(n, kBlock, threads, [&](unsigned, std::size_t b, std::size_t begin, std::size_t end) {
    std::size_t* count = &at[b * kShards];
    for (std::size_t i = begin; i < end; ++i) ++count[shard_of(i)];
  });
  start.assign(kShards + 1, 0);
  std::size_t next = 0;
  for (std::size_t s = 0; s < kShards; ++s) {
    start[s] = next;
    for (std::size_t b = 0; b < blocks; ++b) {
      const std::size_t count = at[b * kShards + s];
      at[b * kShards + s] = next;
      next += count;
    }
  }
  start[kShards] = next;
  out.resize(n);
  runtime::parallel_for_blocks(n, kBlock, threads, [&](unsigned, std::size_t b, std::size_t begin, std::size_t end) {
    std::size_t* place = &at[b * kShards];
    for (std::size_t i = begin; i < end; ++i) out[place[shard_of(i)]++] = make(i);
  });
}

/// Numbers the `n` items of a shard by first use, items equal by same(a, b) sharing a number:
/// number[i] for i in [0, n), counting up from 0; returns how many numbers. An open-addressing
/// table, slots chosen by the low bits of hash(i), holds each number's first item (n < 2^32).
template <class Hash, class Same>
std::uint32_t number_by_first_use(std::size_t n, const Hash& hash, const Same& same, std::uint32_t* number) {
  std::size_t size = 16;
  while (size < 2 * n) size *= 2;
  std::vector<std::uint32_t> table(size, UINT32_MAX);  // a number's first item
  std::uint32_t next = 0;
  for (std::size_t i = 0; i < n; ++i) {
    std::size_t h = static_cast<std::size_t>(hash(i)) & (size - 1);
    while (table[h] != UINT32_MAX && !same(table[h], i)) h = (h + 1) & (size - 1);
    if (table[h] == UINT32_MAX) {
      table[h] = static_cast<std::uint32_t>(i);
      number[i] = next++;
    } else {
      number[i] = number[table[h]];
    }
  }
  return next;
}

using geometry::mix64;
using geometry::point_hash;  // -0.0 hashed as 0.0, as == compares them

/// The uses of the edges of `faces` (corners in all, below 2^32), grouped so that the uses of
/// one edge are adjacent, on `threads` threads: the corners scattered into shards by their
/// point's hash and numbered in each shard (an open-addressing table, points equal by ==), each
/// edge keyed by its two end points' numbers, the uses scattered into shards by their key's hash
/// and grouped in each shard (a table of its keys). Neither the order of the groups nor the
/// order within a group is the serial sort's; the part search below does not depend on them.
runtime::UninitVector<EdgeUse> grouped_edge_uses(const Scene& scene, const std::vector<std::size_t>& faces,
                                                 std::size_t corners, unsigned threads) {
  // Every array sized by the corners is written in full by a parallel loop: UninitVector, so
  // that their pages are first touched there and not zeroed on this thread beforehand.
  std::vector<std::size_t> offset(faces.size() + 1, 0);  // each face's first corner
  runtime::UninitVector<std::uint32_t> face_of(corners);
  for (std::size_t i = 0; i < faces.size(); ++i) offset[i + 1] = offset[i] + scene.faces[faces[i]].vertices.size();
  constexpr std::size_t kFaceBlock = 4096;
  runtime::parallel_for_blocks(faces.size(), kFaceBlock, threads, [&](unsigned, std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
      std::fill(face_of.begin() + static_cast<std::ptrdiff_t>(offset[i]), face_of.begin() + static_cast<std::ptrdiff_t>(offset[i + 1]),
                static_cast<std::uint32_t>(i));
  });
  auto point = [&](std::size_t c) -> const glm::dvec3& {
    return scene.faces[faces[face_of[c]]].vertices[c - offset[face_of[c]]];
  };
  // Each corner's point with its hash and corner, by shard (the hash's top byte).
  struct Corner {
    glm::dvec3 p;
    std::uint32_t corner, hash;  // the hash's low bits: the slot in the shard's table
  };
  runtime::UninitVector<Corner> by_shard;
  std::vector<std::size_t> start;
  {
    runtime::UninitVector<std::uint64_t> hash(corners);
    runtime::parallel_for_blocks(corners, std::size_t{1} << 16, threads, [&](unsigned, std::size_t, std::size_t begin, std::size_t end) {
      for (std::size_t c = begin; c < end; ++c) hash[c] = point_hash(point(c));
    });
    scatter_by_shard(
        corners, threads, [&](std::size_t c) { return static_cast<std::size_t>(hash[c] >> 56); },
        [&](std::size_t c) { return Corner{point(c), static_cast<std::uint32_t>(c), static_cast<std::uint32_t>(hash[c])}; },
        by_shard, start);
  }
  // Vertex numbers: within a shard by first use (number_by_first_use), then offset by the shards before it.
  runtime::UninitVector<std::uint32_t> local(corners);  // by shard order: the corner's number in its shard
  std::vector<std::size_t> distinct(kShards + 1, 0);
  runtime::parallel_for(kShards, threads, [&](unsigned, std::size_t s) {
    const Corner* c = by_shard.data() + start[s];
    distinct[s] = number_by_first_use(
        start[s + 1] - start[s], [&](std::size_t i) { return c[i].hash; },
        [&](std::size_t a, std::size_t b) { return c[a].p == c[b].p; }, local.data() + start[s]);
  });
  std::size_t base = 0;
  for (std::size_t s = 0; s < kShards; ++s) {
    const std::size_t n = distinct[s];
    distinct[s] = base;
    base += n;
  }
  runtime::UninitVector<std::uint32_t> vertex(corners);  // by corner: its point's number
  runtime::parallel_for(kShards, threads, [&](unsigned, std::size_t s) {
    const auto shift = static_cast<std::uint32_t>(distinct[s]);
    for (std::size_t k = start[s]; k < start[s + 1]; ++k) vertex[by_shard[k].corner] = local[k] + shift;
  });
  by_shard = {};
  local = {};
  // Each corner's edge (to the next corner of its face), by shard of its key's hash.
  auto use = [&](std::size_t c) {
    const std::size_t i = face_of[c];
    const std::uint64_t p = vertex[c], q = vertex[c + 1 < offset[i + 1] ? c + 1 : offset[i]];
    const bool forward = p < q;
    return EdgeUse{forward ? (p << 32 | q) : (q << 32 | p), static_cast<std::uint32_t>(i), forward};
  };
  runtime::UninitVector<EdgeUse> uses;
  scatter_by_shard(
      corners, threads, [&](std::size_t c) { return static_cast<std::size_t>(mix64(use(c).key) >> 56); }, use, uses,
      start);
  vertex = {};
  face_of = {};
  // Within a shard, the uses of one edge made adjacent: each key's group numbered by first use
  // (number_by_first_use), then the uses placed group after group.
  runtime::UninitVector<EdgeUse> grouped(corners);
  runtime::parallel_for(kShards, threads, [&](unsigned, std::size_t s) {
    const std::size_t n = start[s + 1] - start[s];
    const EdgeUse* u = uses.data() + start[s];
    std::vector<std::uint32_t> group(n);  // each use's group
    const std::uint32_t groups = number_by_first_use(
        n, [&](std::size_t i) { return mix64(u[i].key); },
        [&](std::size_t a, std::size_t b) { return u[a].key == u[b].key; }, group.data());
    std::vector<std::uint32_t> place(groups, 0);  // each group's size, then its next place
    for (const std::uint32_t g : group) ++place[g];
    std::uint32_t next = 0;
    for (std::uint32_t& p : place) {
      const std::uint32_t count = p;
      p = next;
      next += count;
    }
    for (std::size_t k = 0; k < n; ++k) grouped[start[s] + place[group[k]]++] = uses[start[s] + k];
  });
  return grouped;
}

/// The uses of the edges of `faces`, sorted by their end points' coordinates, one thread: the
/// serial reference (validate_scene_reference) of grouped_edge_uses. Keys are the group numbers.
runtime::UninitVector<EdgeUse> sorted_edge_uses(const Scene& scene, const std::vector<std::size_t>& faces) {
  struct CoordinateUse {
    EdgeKey key;
    bool forward;
    std::size_t face;
  };
  std::vector<CoordinateUse> uses;
  for (std::size_t i = 0; i < faces.size(); ++i) {
    const std::vector<glm::dvec3>& v = scene.faces[faces[i]].vertices;
    for (std::size_t a = 0; a < v.size(); ++a) {
      const glm::dvec3& p = v[a];
      const glm::dvec3& q = v[(a + 1) % v.size()];
      const bool forward = EdgeKey{p, q} < EdgeKey{q, p};
      uses.push_back({forward ? EdgeKey{p, q} : EdgeKey{q, p}, forward, i});
    }
  }
  std::sort(uses.begin(), uses.end(), [](const CoordinateUse& x, const CoordinateUse& y) { return x.key < y.key; });
  runtime::UninitVector<EdgeUse> edges;
  edges.reserve(uses.size());
  std::uint64_t group = 0;
  for (std::size_t i = 0; i < uses.size(); ++i) {
    if (i > 0 && !(uses[i].key.a == uses[i - 1].key.a && uses[i].key.b == uses[i - 1].key.b)) ++group;
    edges.push_back({group, static_cast<std::uint32_t>(uses[i].face), uses[i].forward});
  }
  return edges;
}

/// Signed volume of a part (divergence theorem over fan triangles; its faces are
/// faces[member[k]] for k in [begin, end)), relative to one vertex of the part to keep digits.
long double part_volume(const Scene& scene, const std::vector<std::size_t>& faces, const std::vector<std::size_t>& member,
                        std::size_t begin, std::size_t end) {
  using Real = long double;
  const glm::dvec3 origin = scene.faces[faces[member[begin]]].vertices[0];
  Real volume = 0;
  for (std::size_t k = begin; k < end; ++k) {
    const std::vector<glm::dvec3>& v = scene.faces[faces[member[k]]].vertices;
    auto rel = [&](const glm::dvec3& p, int c) { return Real(p[c]) - Real(origin[c]); };
    for (std::size_t i = 1; i + 1 < v.size(); ++i) {
      const glm::dvec3 &a = v[0], &b = v[i], &c = v[i + 1];
      const Real ax = rel(a, 0), ay = rel(a, 1), az = rel(a, 2);
      const Real bx = rel(b, 0), by = rel(b, 1), bz = rel(b, 2);
      const Real cx = rel(c, 0), cy = rel(c, 1), cz = rel(c, 2);
      volume += ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx);
    }
  }
  return volume;
}

/// What the part search finds of each face of a mesh (by index into its list of faces): its
/// part's root (the part's lowest face), whether one of its edge runs is open (used once, or three
/// times or more: the run's first use's face is marked) or used twice the same way
/// (inconsistent), and with `orient` each face's manifold neighbours (other face, same way).
/// (UninitVector: the parallel search writes every entry, on the thread of its block.)
struct FaceParts {
  runtime::UninitVector<std::size_t> root_of;
  runtime::UninitVector<char> open, inconsistent;
  std::vector<std::vector<std::pair<std::size_t, bool>>> neighbours;
};

/// The part search over `edges` (the uses of one edge adjacent) of a mesh of `n` faces, on one
/// thread: a union-find whose lower root becomes the root.
FaceParts find_parts(const runtime::UninitVector<EdgeUse>& edges, std::size_t n, bool orient) {
  FaceParts parts;
  std::vector<std::size_t> parent(n);
  for (std::size_t i = 0; i < n; ++i) parent[i] = i;
  auto root = [&](std::size_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  // The lower root becomes the root: a part's root is its lowest face, whatever the order.
  auto unite = [&](std::size_t a, std::size_t b) {
    a = root(a);
    b = root(b);
    if (a < b)
      parent[b] = a;
    else if (b < a)
      parent[a] = b;
  };
  parts.open.assign(n, 0);
  parts.inconsistent.assign(n, 0);
  parts.neighbours.resize(orient ? n : 0);
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i + 1;
    while (j < edges.size() && edges[i].key == edges[j].key) ++j;
    for (std::size_t k = i + 1; k < j; ++k) unite(edges[i].face, edges[k].face);
    // Closed: every edge exactly twice (once: a border; three times or more: non-manifold).
    if (j - i != 2) {
      parts.open[edges[i].face] = 1;
    } else {
      const bool same_way = edges[i].forward == edges[i + 1].forward;
      if (same_way) parts.inconsistent[edges[i].face] = 1;
      if (orient) {
        parts.neighbours[edges[i].face].push_back({edges[i + 1].face, same_way});
        parts.neighbours[edges[i + 1].face].push_back({edges[i].face, same_way});
      }
    }
    i = j;
  }
  parts.root_of.resize(n);
  for (std::size_t f = 0; f < n; ++f) parts.root_of[f] = root(f);
  return parts;
}

/// find_parts without `orient` on `threads` threads, for meshes below 2^32 faces: the edge runs
/// in pieces, each piece's runs on one thread, joined in a union-find of atomic parents where a
/// root is only ever linked under a lower root (a compare-and-swap that fails when it is no
/// longer a root, and is tried again) and a face's parent only ever moves to one of its
/// ancestors (path splitting). So every parent is below its child, and each part's root is its
/// lowest face as on one thread: the same result, whatever the threads' order. (A million faces
/// took a tenth of a second of one thread here, the other waiting.)
FaceParts find_parts_parallel(const runtime::UninitVector<EdgeUse>& edges, std::size_t n, unsigned threads) {
  // Default-initialised atomics (C++17: no value), each first written by a parallel loop.
  std::unique_ptr<std::atomic<std::uint32_t>[]> parent(new std::atomic<std::uint32_t>[n]);
  std::unique_ptr<std::atomic<unsigned char>[]> flags(new std::atomic<unsigned char>[n]);
  constexpr std::size_t kBlock = std::size_t{1} << 16;
  runtime::parallel_for_blocks(n, kBlock, threads, [&](unsigned, std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t f = begin; f < end; ++f) {
      parent[f].store(static_cast<std::uint32_t>(f), std::memory_order_relaxed);
      flags[f].store(0, std::memory_order_relaxed);
    }
  });
  // Relaxed throughout: each step rests on one location's value, and the loop's end orders the
  // result before it is read.
  auto root = [&](std::uint32_t x) {
    std::uint32_t p = parent[x].load(std::memory_order_relaxed);
    while (p != x) {
      const std::uint32_t grandparent = parent[p].load(std::memory_order_relaxed);
      if (grandparent != p) parent[x].compare_exchange_weak(p, grandparent, std::memory_order_relaxed);
      x = p;
      p = parent[x].load(std::memory_order_relaxed);
    }
    return x;
  };
  auto unite = [&](std::uint32_t a, std::uint32_t b) {
    for (;;) {
      a = root(a);
      b = root(b);
      if (a == b) return;
      if (a < b) std::swap(a, b);  // a: the higher root, linked under b while it is still a root
      std::uint32_t expected = a;
      if (parent[a].compare_exchange_strong(expected, b, std::memory_order_relaxed)) return;
    }
  };
  constexpr unsigned char kOpen = 1, kInconsistent = 2;
  // Pieces of the runs: cut at most a few per thread, each moved forward to a run's start.
  const std::size_t m = edges.size();
  const std::size_t pieces = std::max<std::size_t>(1, std::min<std::size_t>(m / 4096, std::size_t{8} * threads));
  std::vector<std::size_t> cut(pieces + 1, m);
  cut[0] = 0;
  for (std::size_t k = 1; k < pieces; ++k) {
    std::size_t c = std::max(cut[k - 1], m * k / pieces);
    while (c > 0 && c < m && edges[c].key == edges[c - 1].key) ++c;
    cut[k] = c;
  }
  runtime::parallel_for(pieces, threads, [&](unsigned, std::size_t k) {
    for (std::size_t i = cut[k]; i < cut[k + 1];) {
      std::size_t j = i + 1;
      while (j < m && edges[i].key == edges[j].key) ++j;
      for (std::size_t u = i + 1; u < j; ++u) unite(edges[i].face, edges[u].face);
      if (j - i != 2)
        flags[edges[i].face].fetch_or(kOpen, std::memory_order_relaxed);
      else if (edges[i].forward == edges[i + 1].forward)
        flags[edges[i].face].fetch_or(kInconsistent, std::memory_order_relaxed);
      i = j;
    }
  });
  FaceParts parts;
  parts.root_of.resize(n);
  parts.open.resize(n);
  parts.inconsistent.resize(n);
  runtime::parallel_for_blocks(n, kBlock, threads, [&](unsigned, std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t f = begin; f < end; ++f) {
      parts.root_of[f] = root(static_cast<std::uint32_t>(f));
      const unsigned char flag = flags[f].load(std::memory_order_relaxed);
      parts.open[f] = (flag & kOpen) != 0;
      parts.inconsistent[f] = (flag & kInconsistent) != 0;
    }
  });
  return parts;
}

/// What check_orientation found in (or did to) one closed part.
enum Outcome : char { kFine, kMixed, kOneSided, kInward };
struct PartOutcome {
  Outcome outcome = kFine;
  bool made_consistent = false;
  std::vector<std::size_t> flipped;  // made consistent: the faces reversed
};

/// check_orientation's warnings for the closed parts of a mesh (in the parts' order): one per
/// part fixed or left one-sided, one for all parts of inconsistent orientation, one for all
/// parts that point inward.
void report_parts(const Scene& scene, std::size_t mesh_index, bool orient, std::size_t parts,
                  const std::vector<std::size_t>& faces, const std::vector<std::size_t>& closed,
                  const std::vector<PartOutcome>& outcome, const std::vector<std::size_t>& first,
                  const std::vector<std::size_t>& member, std::vector<Warning>& warnings) {
  const Mesh& mesh = scene.meshes[mesh_index];
  auto part_of = [&](std::size_t r) {
    return std::vector<std::size_t>(member.begin() + static_cast<std::ptrdiff_t>(first[r]),
                                    member.begin() + static_cast<std::ptrdiff_t>(first[r + 1]));
  };
  auto face_ids = [&](const std::vector<std::size_t>& local) {
    std::vector<std::size_t> ids;
    for (std::size_t f : local) ids.push_back(faces[f]);
    return ids;
  };
  const SourceLocation where{scene.source.string(), "meshes[" + std::to_string(mesh_index) + "]"};
  const std::string name = "mesh \"" + mesh.name + "\"";
  auto part_text = [&](const std::vector<std::size_t>& part) {
    return parts == 1 ? name + " (closed, " + list_faces(scene, face_ids(part)) + ")"
                      : name + ": the closed part of " + list_faces(scene, face_ids(part));
  };
  std::size_t inward_parts = 0, mixed_parts = 0;
  std::vector<std::size_t> first_inward, first_mixed;
  for (std::size_t p = 0; p < closed.size(); ++p) {
    const PartOutcome& o = outcome[p];
    const std::size_t r = closed[p];
    if (o.outcome == kMixed) {
      if (mixed_parts++ == 0) first_mixed = part_of(r);
      continue;
    }
    if (o.outcome == kOneSided) {
      warnings.push_back({where, part_text(part_of(r)) + " cannot be oriented consistently (a one-sided surface, like "
                                                         "a Moebius strip); its faces were left as they are"});
      continue;
    }
    if (o.made_consistent)
      warnings.push_back({where, part_text(part_of(r)) + " had inconsistent face orientation (orient outward): to "
                                     "agree with face " + std::to_string(faces[r]) + ", reversed " +
                                     list_faces(scene, face_ids(o.flipped))});
    if (o.outcome == kInward) {
      if (orient)
        warnings.push_back({where, part_text(part_of(r)) + " pointed inward (negative signed volume): its " +
                                       std::to_string(first[r + 1] - first[r]) + " faces were reversed (orient outward)"});
      else if (inward_parts++ == 0)
        first_inward = part_of(r);
    }
  }
  // One part: "mesh "m" is closed, <single> (faces ...)"; else how many parts, and the first's faces.
  auto describe = [&](std::size_t count, const std::vector<std::size_t>& first_part, const std::string& single,
                      const std::string& plural) {
    const std::string listed = list_faces(scene, face_ids(first_part));
    if (parts == 1) return name + " is closed, " + single + " (" + listed + ")";
    return name + " has " + std::to_string(count) + " closed part" + (count == 1 ? "" : "s") + " (of " +
           std::to_string(parts) + "; the first has " + listed + ") " + plural;
  };
  if (mixed_parts > 0)
    warnings.push_back({where, describe(mixed_parts, first_mixed, "with inconsistent face orientation",
                                        "with inconsistent face orientation") +
                                   ": some edge is run the same way by both of its faces, so some faces' fronts point "
                                   "inward and those faces will be in their own (attached) shadow; check the vertex "
                                   "order of its faces, or orient it (\"orient\": \"outward\", --orient-outward)"});
  if (inward_parts > 0)
    warnings.push_back({where, describe(inward_parts, first_inward, "and its faces point inward", "whose faces point inward") +
                                   " (negative signed volume): they are lit only from inside, as for a room seen from "
                                   "within; if it is a solid seen from outside, reverse the vertex order of its faces, "
                                   "or orient it (\"orient\": \"outward\", --orient-outward) (this is only a warning)"});
}

/// Checks the closed parts of a mesh (faces joined by shared edges, every edge shared by exactly
/// two faces of the part): faces that point inward, or neighbours that disagree, read silently as
/// attached shadow, so each such part gets a warning naming the mesh and its first faces. With
/// `orient` (Mesh::orient_outward, LoadOptions::orient_outward), such parts are fixed instead: the
/// faces of an inconsistent part are made to agree with its first face (breadth-first over shared
/// edges), then a part with negative signed volume is reversed; the warning says what changed.
/// Open parts (a ground plane, a single wall, a box without a lid) say nothing about inside and
/// outside and are left alone.
///
/// Parts are taken in the order of their first faces (each part's union-find root is its lowest
/// face, whatever order the unions come in), so the outcome does not depend on how the edge uses
/// were grouped: on `threads` threads (grouped_edge_uses, the parts checked in parallel) it is
/// the serial `reference`'s (sorted_edge_uses, one thread) for any thread count.
void check_orientation(Scene& scene, std::size_t mesh_index, bool orient, std::vector<Warning>& warnings,
                       bool reference, unsigned threads) {
  const Mesh& mesh = scene.meshes[mesh_index];
  std::vector<std::size_t> faces;  // face_ids of the mesh's non-degenerate faces
  std::size_t corners = 0;
  for (std::size_t f = mesh.first_face; f < mesh.first_face + mesh.face_count && f < scene.faces.size(); ++f) {
    const Face& face = scene.faces[f];
    if (face.mesh != mesh_index || face.degenerate) continue;
    faces.push_back(f);
    corners += face.vertices.size();
  }
  if (faces.size() < 2) return;
  if (reference) threads = 1;
  // The coordinate sort for the reference, for small meshes (where the shards' tables would
  // cost more than the sort) and beyond 2^32 corners (vertex numbers and face indices would not
  // fit); else the parallel grouping.
  const bool grouped = !reference && faces.size() >= kLargeMesh && corners < (std::size_t{1} << 32);
  const runtime::UninitVector<EdgeUse> edges =
      grouped ? grouped_edge_uses(scene, faces, corners, threads) : sorted_edge_uses(scene, faces);
  const std::size_t n = faces.size();
  // With `orient` (neighbours), on one thread: only a scene that asks for it.
  const FaceParts found = grouped && !orient && threads > 1 && n < (std::size_t{1} << 32)
                              ? find_parts_parallel(edges, n, threads)
                              : find_parts(edges, n, orient);
  const auto& root_of = found.root_of;
  const auto& open = found.open;
  const auto& inconsistent = found.inconsistent;
  const auto& neighbours = found.neighbours;
  // Each part's faces, ascending, by root (a counting sort: members of part r are
  // member[first[r], first[r + 1])).
  std::vector<std::size_t> first(n + 1, 0), member(n);
  std::vector<char> part_open(n, 0), part_inconsistent(n, 0);
  for (std::size_t f = 0; f < n; ++f) {
    ++first[root_of[f] + 1];
    part_open[root_of[f]] |= open[f];
    part_inconsistent[root_of[f]] |= inconsistent[f];
  }
  for (std::size_t r = 0; r < n; ++r) first[r + 1] += first[r];
  {
    std::vector<std::size_t> next(first.begin(), first.end() - 1);
    for (std::size_t f = 0; f < n; ++f) member[next[root_of[f]]++] = f;
  }
  auto reverse_face = [&](std::size_t f) {
    std::vector<glm::dvec3>& v = scene.faces[faces[f]].vertices;
    std::reverse(v.begin(), v.end());
  };
  auto volume_of = [&](std::size_t r) { return part_volume(scene, faces, member, first[r], first[r + 1]); };
  // Each closed part on its own (in parallel: a part changes only its own faces): made
  // consistent and outward with `orient`, else only looked at.
  std::vector<std::size_t> closed;  // roots, ascending
  std::size_t parts = 0;
  for (std::size_t r = 0; r < n; ++r) {
    if (root_of[r] != r) continue;
    ++parts;
    if (!part_open[r]) closed.push_back(r);
  }
  std::vector<PartOutcome> outcome(closed.size());
  // A part's search touches only its own faces, reset before it starts: one array for all.
  std::vector<int> flip(orient ? n : 0, -1);
  runtime::parallel_for_blocks(closed.size(), 64, threads, [&](unsigned, std::size_t, std::size_t begin, std::size_t end) {
    std::vector<std::size_t> queue;
    for (std::size_t p = begin; p < end; ++p) {
      const std::size_t r = closed[p];
      PartOutcome& o = outcome[p];
      if (part_inconsistent[r]) {
        if (!orient) {
          o.outcome = kMixed;
          continue;
        }
        // Breadth-first from the part's first face: a neighbour across an edge run the same way
        // is flipped relative to the face it was reached from.
        queue.assign(1, r);
        flip[r] = 0;
        bool orientable = true;
        for (std::size_t q = 0; q < queue.size(); ++q) {
          const std::size_t f = queue[q];
          for (const auto& [g, same_way] : neighbours[f]) {
            const int want = flip[f] ^ (same_way ? 1 : 0);
            if (flip[g] < 0) {
              flip[g] = want;
              queue.push_back(g);
            } else if (flip[g] != want) {
              orientable = false;
            }
          }
        }
        if (!orientable) {
          o.outcome = kOneSided;
          continue;
        }
        o.made_consistent = true;
        for (std::size_t k = first[r]; k < first[r + 1]; ++k)
          if (flip[member[k]] == 1) {
            reverse_face(member[k]);
            o.flipped.push_back(member[k]);
          }
      }
      if (volume_of(r) < 0) {
        o.outcome = kInward;
        if (orient)
          for (std::size_t k = first[r]; k < first[r + 1]; ++k) reverse_face(member[k]);
      }
    }
  });
  report_parts(scene, mesh_index, orient, parts, faces, closed, outcome, first, member, warnings);
}

}  // namespace

/// Every mesh's orientation check, the warnings in mesh order. Meshes below kLargeMesh faces
/// (a building each, say) are checked many at once, one thread each; larger ones one after the
/// other on every thread. `reference`: one mesh after the other, one thread, the coordinate sort.
void check_orientations(Scene& scene, const LoadOptions& options, bool reference, unsigned threads,
                        std::vector<Warning>& warnings) {
  std::vector<std::vector<Warning>> per_mesh(scene.meshes.size());
  auto orient = [&](std::size_t m) { return options.orient_outward || scene.meshes[m].orient_outward; };
  if (reference) {
    for (std::size_t m = 0; m < scene.meshes.size(); ++m) check_orientation(scene, m, orient(m), per_mesh[m], true, 1);
  } else {
    runtime::parallel_for_blocks(scene.meshes.size(), 16, threads, [&](unsigned, std::size_t, std::size_t begin, std::size_t end) {
      for (std::size_t m = begin; m < end; ++m)
        if (scene.meshes[m].face_count < kLargeMesh) check_orientation(scene, m, orient(m), per_mesh[m], false, 1);
    });
    for (std::size_t m = 0; m < scene.meshes.size(); ++m)
      if (scene.meshes[m].face_count >= kLargeMesh) check_orientation(scene, m, orient(m), per_mesh[m], false, threads);
  }
  for (std::vector<Warning>& mesh_warnings : per_mesh)
    for (Warning& w : mesh_warnings) warnings.push_back(std::move(w));
}


}  // namespace shadow::validation
