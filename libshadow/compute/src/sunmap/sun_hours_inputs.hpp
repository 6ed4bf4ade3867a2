// SPDX-License-Identifier: GPL-3.0-or-later
// The sun-hours map's inputs checked (sun_hours_inputs.cpp): one clear error naming the item and
// the problem, before any work.
#pragma once

#include <shadow/scene.hpp>
#include <shadow/sun_hours.hpp>

#include <gmpxx.h>

#include <cstddef>
#include <vector>

namespace shadow::sunmap {

/// The instants' weights, their lights and weights checked.
std::vector<double> checked_hours(const std::vector<SunHoursInstant>& instants);

/// The weights as the map sums them: each the fraction of denominator at most a million that
/// rounds to it, where there is one (the intended 1/6 h of a 10-minute step, not the double
/// just below it: twelve of them make exactly 2 hours), else the double's own value. Two such
/// fractions are at least 1e-12 apart, so at most one lies within a double's rounding.
std::vector<mpq_class> exact_hours(const std::vector<double>& hours);

/// The face ids checked, ascending, repeats dropped.
std::vector<std::size_t> checked_faces(const Scene& scene, const std::vector<std::size_t>& faces_in);

/// Checks and sorts the levels: ascending, repeats dropped.
std::vector<double> checked_levels(const std::vector<double>& levels);

}  // namespace shadow::sunmap
