// SPDX-License-Identifier: GPL-3.0-or-later
#include "radiosity/receivers.hpp"

#include "runtime/parallel.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace shadow::radiosity {
namespace {

/// The receiving rule of an element at distance `gap` from a shooter (R: the sum of their
/// circumradii): beyond 6 R the centroid; within, the 3-point rule (degree 2); within `close` R
/// (2 for shooting), where the point form factor varies fast (logarithmically along a shared
/// edge), a 4 x 4 collapsed Gauss rule. Returns the estimate and sets `change` to its difference from the rule below.
/// With `spread` (two values): the first two interior points' differences from the three's mean
/// (the third's is minus their sum), the element's gradient seen at half its size; 0 beyond 6 R.
template <class PointFactor>
double integrate_over_element(const Element& e, double gap, double reach, const PointFactor& at, double& change,
                              double close, float* spread = nullptr) {
  static const std::pair<std::vector<double>, std::vector<double>> gauss = [] {
    std::pair<std::vector<double>, std::vector<double>> g;
    gauss_legendre01(4, g.first, g.second);
    return g;
  }();
  change = 0.0;
  double f = at(e.centroid);
  if (spread) spread[0] = spread[1] = 0.0f;
  if (gap < 6.0 * reach) {
    double point[3];
    for (int c = 0; c < 3; ++c) point[c] = at(interior_point(e.triangle, c));
    const double f3 = (point[0] + point[1] + point[2]) / 3.0;
    change = std::abs(f3 - f);
    f = f3;
    if (spread) spread[0] = static_cast<float>(point[0] - f3), spread[1] = static_cast<float>(point[1] - f3);
  }
  if (gap < close * reach) {
    const Triangle& t = e.triangle;
    double f16 = 0.0;
    for (std::size_t a = 0; a < gauss.first.size(); ++a)
      for (std::size_t b = 0; b < gauss.first.size(); ++b) {
        const double u = gauss.first[a], v = gauss.first[b];
        f16 += 2.0 * u * gauss.second[a] * gauss.second[b] * at(t[0] + u * (t[1] - t[0]) + u * v * (t[2] - t[1]));
      }
    change = std::abs(f16 - f);
    f = f16;
  }
  return f;
}

}  // namespace

Receivers::Receivers(const Scene& scene, unsigned threads, bool exact)
    : exact_(exact), culler_(scene), workers_(std::max(1u, threads)) {
  if (exact) view_ = std::make_unique<ShooterView>(scene, threads);
}

void Receivers::receive(const std::vector<Patch>& patches, const std::vector<Element>& elements, const Patch& s,
                        unsigned threads, std::vector<double>& factor, std::vector<double>& quad,
                        std::vector<float>* spread, const std::vector<char>* only) {
  const std::vector<glm::dvec3> source = {s.triangle[0], s.triangle[1], s.triangle[2]};
  factor.assign(elements.size(), 0.0);
  quad.assign(elements.size(), 0.0);
  if (spread) spread->assign(2 * elements.size(), 0.0f);
  float* spread_at = spread ? spread->data() : nullptr;
  if (exact_) {
    std::vector<std::vector<glm::dvec3>> pieces;
    if (s.count > 1)
      for (std::size_t i = s.first; i < s.first + s.count; ++i)
        pieces.push_back({elements[i].triangle[0], elements[i].triangle[1], elements[i].triangle[2]});
    view_->set_shooter(s.face, source, std::move(pieces));
    runtime::parallel_for(elements.size(), threads, [&](unsigned worker, std::size_t i) {
      const Element& e = elements[i];
      if (only && !(*only)[i]) return;
      if (e.face == s.face || !faces_each_other(e.triangle, e.face, s.triangle, s.face)) return;
      const double gap = glm::length(e.centroid - s.centroid), reach = e.radius + s.radius;
      factor[i] = integrate_over_element(e, gap, reach, [&](const glm::dvec3& p) {
        return view_->evaluate(worker, {e.face, p});
      }, quad[i], 2.0, spread_at ? spread_at + 2 * i : nullptr);
    });
    return;
  }
  // One shaft per receiving patch serves all its elements (each element's shaft lies inside it).
  const SourceChart chart(source);
  runtime::parallel_for(patches.size(), threads, [&](unsigned worker, std::size_t r) {
    const Patch& receiver = patches[r];
    if (receiver.face == s.face || !faces_each_other(receiver.triangle, receiver.face, s.triangle, s.face)) return;
    const char* wanted = only ? only->data() + receiver.first : nullptr;
    if (wanted && std::find(wanted, wanted + receiver.count, 1) == wanted + receiver.count) return;
    receive_patch(workers_[worker], chart, source, elements, receiver, s, &factor[receiver.first], &quad[receiver.first],
                  2.0, spread_at ? spread_at + 2 * receiver.first : nullptr, wanted);
  });
}

bool Receivers::receive_pair(unsigned worker, const std::vector<Element>& elements, const Patch& r, const Patch& s,
                             double close, std::vector<double>& factor, std::vector<double>& quad) {
  factor.assign(r.count, 0.0);
  quad.assign(r.count, 0.0);
  if (r.face == s.face || !faces_each_other(r.triangle, r.face, s.triangle, s.face)) return false;
  const std::vector<glm::dvec3> source = {s.triangle[0], s.triangle[1], s.triangle[2]};
  const SourceChart chart(source);
  return receive_patch(workers_[worker], chart, source, elements, r, s, factor.data(), quad.data(), close);
}

bool Receivers::receive_patch(Worker& w, const SourceChart& chart, const std::vector<glm::dvec3>& source,
                              const std::vector<Element>& elements, const Patch& receiver, const Patch& s,
                              double* factor, double* quad, double close, float* spread, const char* only) {
  if (culler_.candidates({receiver.triangle[0], receiver.triangle[1], receiver.triangle[2]}, receiver.face, source,
                         s.face, w.shaft, w.faces))
    return false;  // one face hides the shooter from all of the receiving patch
  w.occluders.clear();
  for (std::size_t f : w.faces) w.occluders.push_back(&culler_.vertices(f));
  const glm::dvec3& nr = normals()[receiver.face];
  bool any = false;
  for (std::size_t k = 0; k < receiver.count; ++k) {
    const Element& e = elements[receiver.first + k];
    if ((only && !only[k]) || !faces_each_other(e.triangle, e.face, s.triangle, s.face)) continue;
    const double gap = glm::length(e.centroid - s.centroid), reach = e.radius + s.radius;
    factor[k] = integrate_over_element(e, gap, reach, [&](const glm::dvec3& p) {
      return w.occluders.empty() ? chart.unoccluded(p, nr, w.visible) : chart.form_factor(p, nr, w.occluders, w.visible);
    }, quad[k], close, spread ? spread + 2 * k : nullptr);
    any = any || factor[k] > 0.0;
  }
  return any;
}

bool Receivers::faces_each_other(const Triangle& r, std::size_t r_face, const Triangle& s, std::size_t s_face) const {
  const glm::dvec3 &nr = normals()[r_face], &ns = normals()[s_face];
  bool a = false, b = false;
  for (const glm::dvec3& v : r) a = a || glm::dot(ns, v - s[0]) > 0.0;
  for (const glm::dvec3& v : s) b = b || glm::dot(nr, v - r[0]) > 0.0;
  return a && b;
}

}  // namespace shadow::radiosity
