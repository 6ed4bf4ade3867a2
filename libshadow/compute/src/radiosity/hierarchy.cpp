// SPDX-License-Identifier: GPL-3.0-or-later
// Hierarchical radiosity with clusters (Hanrahan, Salzman and Aupperle 1991; Smits, Arvo and
// Greenberg 1994): docs/radiosity.md, "Hierarchical radiosity".
#include "radiosity/hierarchy.hpp"

#include "runtime/parallel.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace shadow::radiosity {
namespace {

constexpr double kPi = 3.14159265358979323846;

/// A small deterministic generator (splitmix64): a link's rays depend on the link alone, so the
/// solution is the same at any thread count.
struct Random {
  std::uint64_t state;
  double next() {
    std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return static_cast<double>(z >> 11) * 0x1.0p-53;
  }
};

/// A uniform point of triangle t from two uniform numbers.
glm::dvec3 point_in(const Triangle& t, double u, double v) {
  const double su = std::sqrt(u);
  return (1.0 - su) * t[0] + su * (1.0 - v) * t[1] + su * v * t[2];
}

}  // namespace

Hierarchy::Hierarchy(const std::vector<Patch>& patches, const std::vector<Element>& elements, Receivers& receivers,
                     const std::vector<char>& can_emit, const HierarchyOptions& options)
    : patches_(patches), elements_(elements), receivers_(receivers), options_(options) {
  const std::size_t n = patches.size();
  if (n == 0) return;
  order_.resize(n);
  std::iota(order_.begin(), order_.end(), 0u);
  nodes_.reserve(2 * n);
  build(0, static_cast<std::uint32_t>(n), can_emit);
  leaf_of_patch_.assign(n, -1);
  // Parts bottom-up: a leaf's one face; a node's the merge of its children's, by face id.
  std::vector<std::vector<Part>> parts(nodes_.size());
  for (std::size_t k = nodes_.size(); k-- > 0;) {
    const Node& node = nodes_[k];
    if (node.left < 0) {
      const Patch& p = patches_[order_[node.first]];
      parts[k] = {{p.face, p.area}};
      leaf_of_patch_[order_[node.first]] = static_cast<std::int32_t>(k);
      continue;
    }
    const std::vector<Part>&a = parts[static_cast<std::size_t>(node.left)], &b = parts[static_cast<std::size_t>(node.right)];
    std::vector<Part>& out = parts[k];
    std::size_t i = 0, j = 0;
    while (i < a.size() || j < b.size()) {
      if (j == b.size() || (i < a.size() && a[i].face < b[j].face)) {
        out.push_back(a[i++]);
      } else if (i == a.size() || b[j].face < a[i].face) {
        out.push_back(b[j++]);
      } else {
        out.push_back({a[i].face, a[i].area + b[j].area});
        ++i, ++j;
      }
    }
  }
  for (std::size_t k = 0; k < nodes_.size(); ++k) {
    nodes_[k].parts_first = static_cast<std::uint32_t>(parts_.size());
    nodes_[k].parts_count = static_cast<std::uint32_t>(parts[k].size());
    parts_.insert(parts_.end(), parts[k].begin(), parts[k].end());
  }

  const unsigned threads = std::max(1u, options_.threads);
  enclosed_.assign(n, 0);
  {
    const std::vector<glm::dvec3>& normals = receivers_.normals();
    const double reach = 4.0 * (nodes_[0].radius + 1.0);
    std::vector<ShaftCuller::Scratch> scratch(threads);
    runtime::parallel_for(n, threads, [&](unsigned worker, std::size_t p) {
      const Patch& patch = patches_[p];
      const glm::dvec3& normal = normals[patch.face];
      const std::size_t hit =
          receivers_.culler().first_hit(patch.centroid, patch.face, patch.centroid + reach * normal, scratch[worker]);
      enclosed_[p] = hit != SIZE_MAX && glm::dot(normals[hit], normal) > 0.0 ? 1 : 0;
    });
  }
  std::vector<std::pair<std::uint32_t, std::uint32_t>> near_pairs, far_pairs;
  link(near_pairs, far_pairs);
  const std::size_t total = near_pairs.size() + far_pairs.size();
  auto progress = [&](std::size_t before, std::size_t done) {
    if (options_.progress && total > 0) options_.progress(static_cast<double>(before + done) / static_cast<double>(total));
  };

  // Near pairs: per receiving element, the form factor to the source patch (visibility in
  // doubles), in blocks so that the pairs' scratch stays small.
  std::sort(near_pairs.begin(), near_pairs.end());
  near_begin_.assign(n + 1, 0);
  constexpr std::size_t kBlock = std::size_t(1) << 16;
  std::vector<std::vector<double>> factors(std::min(kBlock, near_pairs.size()));
  std::vector<double> quadrature(factors.size());
  std::vector<char> seen(factors.size());
  std::vector<std::vector<double>> quad(threads);
  for (std::size_t begin = 0; begin < near_pairs.size(); begin += kBlock) {
    const std::size_t count = std::min(kBlock, near_pairs.size() - begin);
    runtime::parallel_for(count, threads, [&](unsigned worker, std::size_t i) {
      const auto [r, s] = near_pairs[begin + i];
      const Patch& receiver = patches_[r];
      seen[i] = receivers_.receive_pair(worker, elements_, receiver, patches_[s], options_.close_rule, factors[i],
                                        quad[worker])
                    ? 1
                    : 0;
      quadrature[i] = 0.0;
      for (std::size_t k = 0; k < receiver.count; ++k)
        quadrature[i] += quad[worker][k] * elements_[receiver.first + k].area;
    }, [&](std::size_t done) { progress(begin, done); });
    for (std::size_t i = 0; i < count; ++i) {
      if (!seen[i]) continue;
      const auto [r, s] = near_pairs[begin + i];
      near_.push_back({r, s, near_factors_.size(), quadrature[i]});
      near_factors_.insert(near_factors_.end(), factors[i].begin(), factors[i].end());
      ++near_begin_[r + 1];
    }
  }
  for (std::size_t p = 0; p < n; ++p) near_begin_[p + 1] += near_begin_[p];

  // Far pairs: one factor per pair of faces, the visibility from rays.
  std::sort(far_pairs.begin(), far_pairs.end());
  std::vector<FarLink> far(far_pairs.size());
  {
    std::vector<ShaftCuller::Scratch> scratch(threads);
    runtime::parallel_for(far_pairs.size(), threads, [&](unsigned worker, std::size_t i) {
      far[i].receiver = far_pairs[i].first;
      far[i].source = far_pairs[i].second;
      make_far_link(far[i], (std::uint64_t(far_pairs[i].first) << 32) ^ far_pairs[i].second, scratch[worker]);
    }, [&](std::size_t done) { progress(near_pairs.size(), done); });
  }
  far_begin_.assign(nodes_.size() + 1, 0);
  for (const FarLink& link : far)
    if (link.visible > 0.0) {
      far_.push_back(link);
      ++far_begin_[link.receiver + 1];
    }
  for (std::size_t k = 0; k < nodes_.size(); ++k) far_begin_[k + 1] += far_begin_[k];
}

std::int32_t Hierarchy::build(std::uint32_t first, std::uint32_t count, const std::vector<char>& can_emit) {
  const std::size_t index = nodes_.size();
  nodes_.emplace_back();
  Node node;
  node.first = first;
  node.count = count;
  glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-lo), clo = lo, chi = hi, weighted(0.0);
  for (std::uint32_t k = first; k < first + count; ++k) {
    const Patch& p = patches_[order_[k]];
    for (const glm::dvec3& v : p.triangle) lo = glm::min(lo, v), hi = glm::max(hi, v);
    clo = glm::min(clo, p.centroid), chi = glm::max(chi, p.centroid);
    weighted += p.area * p.centroid;
    node.area += p.area;
    node.emits = node.emits || can_emit[order_[k]] != 0;
  }
  node.lo = lo;
  node.hi = hi;
  node.centroid = node.area > 0 ? weighted / node.area : 0.5 * (lo + hi);
  for (std::uint32_t k = first; k < first + count; ++k)
    for (const glm::dvec3& v : patches_[order_[k]].triangle)
      node.radius = std::max(node.radius, glm::length(v - node.centroid));
  if (count > 1) {
    // Split at the median of the patches' centroids along the longest side of their box.
    const glm::dvec3 extent = chi - clo;
    const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
    const std::uint32_t half = count / 2;
    std::nth_element(order_.begin() + first, order_.begin() + first + half, order_.begin() + first + count,
                     [&](std::uint32_t a, std::uint32_t b) {
                       const double ca = patches_[a].centroid[axis], cb = patches_[b].centroid[axis];
                       return ca < cb || (ca == cb && a < b);
                     });
    node.left = build(first, half, can_emit);
    node.right = build(first + half, count - half, can_emit);
  }
  nodes_[index] = node;
  return static_cast<std::int32_t>(index);
}

bool Hierarchy::hidden_by_plane(const Node& a, const Node& b) const {
  // A group on one face sees nothing behind its plane, and nothing behind it sees it.
  if (a.parts_count != 1) return false;
  const std::size_t face = parts_[a.parts_first].face;
  const glm::dvec3& n = receivers_.normals()[face];
  const glm::dvec3 origin = patches_[order_[a.first]].triangle[0];
  const double tol = 1e-9 * (a.radius + b.radius + glm::length(a.centroid - b.centroid));
  for (int corner = 0; corner < 8; ++corner) {
    const glm::dvec3 c((corner & 1) ? b.hi.x : b.lo.x, (corner & 2) ? b.hi.y : b.lo.y, (corner & 4) ? b.hi.z : b.lo.z);
    if (glm::dot(n, c - origin) > tol) return false;
  }
  return true;
}

void Hierarchy::link(std::vector<std::pair<std::uint32_t, std::uint32_t>>& near,
                     std::vector<std::pair<std::uint32_t, std::uint32_t>>& far) const {
  std::vector<std::pair<std::uint32_t, std::uint32_t>> stack = {{0u, 0u}};
  while (!stack.empty()) {
    const auto [r, s] = stack.back();
    stack.pop_back();
    const Node &R = nodes_[r], &S = nodes_[s];
    if (!S.emits) continue;  // nothing ever leaves S
    if (r == s) {
      if (R.left < 0) continue;  // a patch does not see itself
      const auto a = static_cast<std::uint32_t>(R.left), b = static_cast<std::uint32_t>(R.right);
      stack.insert(stack.end(), {{a, a}, {a, b}, {b, a}, {b, b}});
      continue;
    }
    if (hidden_by_plane(R, S) || hidden_by_plane(S, R)) continue;
    const double distance = glm::length(R.centroid - S.centroid);
    if (R.radius + S.radius <= options_.separation * distance) {
      far.emplace_back(r, s);
      continue;
    }
    if (R.left < 0 && S.left < 0) {
      const std::uint32_t pr = order_[R.first], ps = order_[S.first];
      if (patches_[pr].face != patches_[ps].face) near.emplace_back(pr, ps);
      continue;
    }
    // Split the larger group (a patch is never split here: its elements receive as they are).
    if (S.left < 0 || (R.left >= 0 && R.radius >= S.radius)) {
      stack.emplace_back(static_cast<std::uint32_t>(R.left), s);
      stack.emplace_back(static_cast<std::uint32_t>(R.right), s);
    } else {
      stack.emplace_back(r, static_cast<std::uint32_t>(S.left));
      stack.emplace_back(r, static_cast<std::uint32_t>(S.right));
    }
  }
}

void Hierarchy::make_far_link(FarLink& link, std::uint64_t seed, ShaftCuller::Scratch& scratch) const {
  const Node &R = nodes_[link.receiver], &S = nodes_[link.source];
  const glm::dvec3 between = R.centroid - S.centroid;
  const double d2 = glm::dot(between, between);
  if (!(d2 > 0.0)) {  // only for groups of no size at one point
    link.visible = 0.0;
    return;
  }
  link.direction = between / std::sqrt(d2);
  link.inverse_square = 1.0 / d2;
  // The rays join points of patches chosen by their area facing the other group.
  const std::vector<glm::dvec3>& normals = receivers_.normals();
  auto weights = [&](const Node& node, double sign, std::vector<double>& cumulative) {
    cumulative.clear();
    double sum = 0.0;
    for (std::uint32_t k = node.first; k < node.first + node.count; ++k) {
      const Patch& p = patches_[order_[k]];
      if (!enclosed_[order_[k]]) sum += p.area * std::max(0.0, sign * glm::dot(normals[p.face], link.direction));
      cumulative.push_back(sum);
    }
    return sum;
  };
  std::vector<double> cr, cs;
  const double wr = weights(R, -1.0, cr), ws = weights(S, 1.0, cs);
  if (!(wr > 0.0) || !(ws > 0.0)) {
    link.visible = 0.0;
    return;
  }
  Random random{seed * 0x2545F4914F6CDD1Dull + 1};
  const int rays = std::max(1, options_.rays);
  double weighted = 0.0, seen = 0.0;
  int unblocked = 0;
  auto pick = [&](const Node& node, const std::vector<double>& cumulative, double total, double u) -> const Patch& {
    const auto at = std::upper_bound(cumulative.begin(), cumulative.end(), u * total) - cumulative.begin();
    return patches_[order_[node.first + std::min<std::size_t>(static_cast<std::size_t>(at), node.count - 1)]];
  };
  for (int k = 0; k < rays; ++k) {
    // Stratified in the choice of patches: ray k takes the k-th slice of each group's weight.
    const Patch& pr = pick(R, cr, wr, (k + random.next()) / rays);
    const Patch& ps = pick(S, cs, ws, ((rays - 1 - k) + random.next()) / rays);
    const glm::dvec3 x = point_in(pr.triangle, random.next(), random.next());
    const glm::dvec3 y = point_in(ps.triangle, random.next(), random.next());
    const glm::dvec3 xy = y - x;
    const double l2 = glm::dot(xy, xy);
    // The patches were drawn by area times their cosine to the link's direction: each ray's
    // kernel over those cosines weighs the pairs as drawing by area alone would.
    const double drawn = -glm::dot(normals[pr.face], link.direction) * glm::dot(normals[ps.face], link.direction);
    const double kernel =
        l2 > 0 && drawn > 0
            ? std::max(0.0, glm::dot(normals[pr.face], xy)) * std::max(0.0, -glm::dot(normals[ps.face], xy)) /
                  (l2 * l2 * drawn)
            : 0.0;
    const bool clear = !receivers_.culler().blocked(x, pr.face, y, ps.face, scratch);
    weighted += kernel;
    if (clear) seen += kernel, ++unblocked;
  }
  link.visible = weighted > 0.0 ? seen / weighted : static_cast<double>(unblocked) / rays;
  const double v = link.visible;
  // The centroid kernel's relative error is about (r_R^2 + r_S^2) / d^2 (between angle^2 / 2
  // and angle^2); the rays' standard error that of a proportion (with one ray's worth added, so
  // that all-clear or all-blocked samples do not claim certainty).
  link.kernel_error = (R.radius * R.radius + S.radius * S.radius) / d2;
  link.sampling_error = std::sqrt((v * (1.0 - v) + 1.0 / rays) / rays);
}

std::vector<double> Hierarchy::patch_radiosity(const std::vector<double>& b) const {
  std::vector<double> patch_b(patches_.size(), 0.0);
  for (std::size_t p = 0; p < patches_.size(); ++p) {
    const Patch& patch = patches_[p];
    double sum = 0.0, area = 0.0;
    for (std::size_t i = patch.first; i < patch.first + patch.count; ++i) {
      sum += b[i] * elements_[i].area;
      area += elements_[i].area;
    }
    patch_b[p] = area > 0 ? sum / area : 0.0;
  }
  return patch_b;
}

void Hierarchy::part_powers(const std::vector<double>& patch_b, std::vector<double>& power) const {
  power.assign(parts_.size(), 0.0);
  for (std::size_t k = nodes_.size(); k-- > 0;) {
    const Node& node = nodes_[k];
    if (node.left < 0) {
      const std::uint32_t p = order_[node.first];
      power[node.parts_first] = patch_b[p] * patches_[p].area;
      continue;
    }
    for_each_child_part(node, [&](std::size_t mine, std::size_t childs) { power[mine] += power[childs]; });
  }
}

template <class Pair>
void Hierarchy::for_each_child_part(const Node& node, const Pair& pair) const {
  for (const std::int32_t child : {node.left, node.right}) {
    const Node& c = nodes_[static_cast<std::size_t>(child)];
    std::size_t i = node.parts_first;
    for (std::size_t j = c.parts_first; j < c.parts_first + c.parts_count; ++j) {
      while (parts_[i].face != parts_[j].face) ++i;  // the child's faces are among the node's, in order
      pair(i, j);
    }
  }
}

double Hierarchy::far_transfer(const FarLink& link, const std::vector<double>& power) const {
  // The source group's radiant intensity towards the receiver (W/sr): each face's power times
  // its cosine over pi (a Lambertian surface).
  const Node& S = nodes_[link.source];
  const std::vector<glm::dvec3>& normals = receivers_.normals();
  double intensity = 0.0;
  for (std::size_t j = S.parts_first; j < S.parts_first + S.parts_count; ++j)
    intensity += power[j] * std::max(0.0, glm::dot(normals[parts_[j].face], link.direction));
  return intensity / kPi * link.inverse_square * link.visible;
}

void Hierarchy::gather(const std::vector<double>& b, const std::vector<double>& direct, std::vector<double>& h) const {
  const std::size_t n = patches_.size();
  const std::vector<double> patch_b = patch_radiosity(b);
  std::vector<double> power, irradiance(parts_.size(), 0.0);
  part_powers(patch_b, power);
  const std::vector<glm::dvec3>& normals = receivers_.normals();
  const unsigned threads = std::max(1u, options_.threads);
  // Each receiving group's faces gather from its links (W/m^2 on a face of that orientation).
  runtime::parallel_for(nodes_.size(), threads, [&](unsigned, std::size_t r) {
    const Node& R = nodes_[r];
    for (std::size_t l = far_begin_[r]; l < far_begin_[r + 1]; ++l) {
      const FarLink& link = far_[l];
      const double per_cosine = far_transfer(link, power);
      for (std::size_t g = R.parts_first; g < R.parts_first + R.parts_count; ++g)
        irradiance[g] += per_cosine * std::max(0.0, -glm::dot(normals[parts_[g].face], link.direction));
    }
  });
  // Pushed down to the patches: a group's irradiance on a face reaches every patch of that face.
  for (std::size_t k = 0; k < nodes_.size(); ++k) {
    const Node& node = nodes_[k];
    if (node.left < 0) continue;
    for_each_child_part(node, [&](std::size_t mine, std::size_t childs) { irradiance[childs] += irradiance[mine]; });
  }
  h.assign(direct.begin(), direct.end());
  runtime::parallel_for(n, threads, [&](unsigned, std::size_t p) {
    const Patch& patch = patches_[p];
    const double far = enclosed_[p] ? 0.0 : irradiance[nodes_[static_cast<std::size_t>(leaf_of_patch_[p])].parts_first];
    for (std::size_t i = patch.first; i < patch.first + patch.count; ++i) h[i] += far;
    for (std::size_t l = near_begin_[p]; l < near_begin_[p + 1]; ++l) {
      const NearLink& link = near_[l];
      const double source = patch_b[link.source];
      for (std::size_t k = 0; k < patch.count; ++k) h[patch.first + k] += near_factors_[link.factors + k] * source;
    }
  });
}

double Hierarchy::link_error(const std::vector<double>& b) const {
  const std::vector<double> patch_b = patch_radiosity(b);
  std::vector<double> power;
  part_powers(patch_b, power);
  const std::vector<glm::dvec3>& normals = receivers_.normals();
  // Per receiving face: the kernel's error adds up (a bias), the rays' sampling errors of
  // different links are independent (their variances add).
  std::size_t faces = 0;
  for (const Part& part : parts_) faces = std::max(faces, part.face + 1);
  std::vector<double> carried(faces, 0.0), bias(faces, 0.0), variance(faces, 0.0);
  for (const FarLink& link : far_) {
    const Node& R = nodes_[link.receiver];
    const double per_cosine = far_transfer(link, power);
    for (std::size_t g = R.parts_first; g < R.parts_first + R.parts_count; ++g) {
      const std::size_t f = parts_[g].face;
      const double watts = per_cosine * parts_[g].area * std::max(0.0, -glm::dot(normals[f], link.direction));
      carried[f] += watts;
      bias[f] += watts * link.kernel_error;
      variance[f] += watts * watts * link.sampling_error * link.sampling_error;
    }
  }
  // Near links: the receiving quadrature's change (three points against the centroid, or 16
  // against three) as shooting states it.
  for (const NearLink& link : near_) {
    const Patch& r = patches_[link.receiver];
    for (std::size_t k = 0; k < r.count; ++k)
      carried[r.face] += near_factors_[link.factors + k] * patch_b[link.source] * elements_[r.first + k].area;
    bias[r.face] += link.quadrature * patch_b[link.source];
  }
  double total = 0.0, error = 0.0;
  for (std::size_t f = 0; f < faces; ++f) {
    total += carried[f];
    error += bias[f] + std::sqrt(variance[f]);
  }
  return total > 0 ? error / total : 0.0;
}

}  // namespace shadow::radiosity
