// SPDX-License-Identifier: GPL-3.0-or-later
// Internal: adaptive refinement of radiosity's elements where the irradiance varies across them
// (docs/radiosity.md, "Adaptive refinement").
#pragma once

#include "radiosity/elements.hpp"

#include <vector>

namespace shadow::radiosity {

/// Each element's estimated squared error of taking one value over it: the integral over the
/// element of (H - its mean)^2 for the linear H whose differences from the mean at the first two
/// interior points of the degree-2 rule (halfway from the centroid to the corners) are
/// spread[2 i], spread[2 i + 1] (the third is minus their sum). At the corners the differences
/// are twice those, and a linear field's integral is area / 12 times the sum of their squares.
std::vector<double> element_errors(const std::vector<Element>& elements, const std::vector<double>& spread);

/// The elements to split, the largest errors first, until what is left of the summed squared
/// error (a split element counting a quarter of its own: four children, each a quarter of the
/// area and half the spread) is at most `target`. An element already split `depth_limit` times
/// (Element::depth) is not split again.
std::vector<char> mark_for_split(const std::vector<Element>& elements, const std::vector<double>& errors, double target,
                                 int depth_limit);

/// Splits each marked element into four at its edges' midpoints (same shape, same orientation),
/// keeping each patch's elements consecutive (Patch::first, Patch::count updated). `origin`: for
/// each new element, its index before when it was kept whole, SIZE_MAX for a piece of a split one.
void split_elements(std::vector<Patch>& patches, std::vector<Element>& elements, const std::vector<char>& marked,
                    std::vector<std::size_t>& origin);

}  // namespace shadow::radiosity
