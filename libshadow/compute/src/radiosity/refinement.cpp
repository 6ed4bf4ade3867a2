// SPDX-License-Identifier: GPL-3.0-or-later
#include "radiosity/refinement.hpp"

#include <algorithm>
#include <cstdint>
#include <numeric>

namespace shadow::radiosity {

std::vector<double> element_errors(const std::vector<Element>& elements, const std::vector<double>& spread) {
  std::vector<double> errors(elements.size(), 0.0);
  for (std::size_t i = 0; i < elements.size(); ++i) {
    const double d0 = 2.0 * spread[2 * i], d1 = 2.0 * spread[2 * i + 1], d2 = -(d0 + d1);
    errors[i] = elements[i].area / 12.0 * (d0 * d0 + d1 * d1 + d2 * d2);
  }
  return errors;
}

std::vector<char> mark_for_split(const std::vector<Element>& elements, const std::vector<double>& errors, double target,
                                 int depth_limit) {
  std::vector<std::size_t> order(errors.size());
  std::iota(order.begin(), order.end(), std::size_t(0));
  // Ties broken by index: the same marks whatever the sort's implementation.
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return errors[a] != errors[b] ? errors[a] > errors[b] : a < b;
  });
  double left = 0.0;
  for (double e : errors) left += e;
  std::vector<char> marked(errors.size(), 0);
  for (std::size_t i : order) {
    if (left <= target || !(errors[i] > 0.0)) break;
    if (elements[i].depth >= depth_limit) continue;
    marked[i] = 1;
    left -= 0.75 * errors[i];
  }
  return marked;
}

void split_elements(std::vector<Patch>& patches, std::vector<Element>& elements, const std::vector<char>& marked,
                    std::vector<std::size_t>& origin) {
  std::vector<Element> out;
  origin.clear();
  out.reserve(elements.size() + 3 * static_cast<std::size_t>(std::count(marked.begin(), marked.end(), 1)));
  for (std::size_t p = 0; p < patches.size(); ++p) {
    Patch& patch = patches[p];
    const std::size_t first = out.size();
    for (std::size_t i = patch.first; i < patch.first + patch.count; ++i) {
      const Element& e = elements[i];
      if (!marked[i]) {
        out.push_back(e);
        origin.push_back(i);
        continue;
      }
      const Triangle& t = e.triangle;
      const glm::dvec3 m01 = 0.5 * (t[0] + t[1]), m12 = 0.5 * (t[1] + t[2]), m20 = 0.5 * (t[2] + t[0]);
      for (const Triangle& child : {Triangle{t[0], m01, m20}, Triangle{m01, t[1], m12}, Triangle{m20, m12, t[2]},
                                    Triangle{m01, m12, m20}}) {
        Element c = make_element(e.face, child, e.fragment, p);
        c.depth = e.depth + 1;
        if (c.area > 0.0) out.push_back(c), origin.push_back(SIZE_MAX);
      }
    }
    patch.first = first;
    patch.count = out.size() - first;
  }
  elements.swap(out);
}

}  // namespace shadow::radiosity
