// SPDX-License-Identifier: GPL-3.0-or-later
// The one place that resolves and checks lights (validation, the face engine, the plane shadows).
#include "core/lights.hpp"

#include "core/input_checks.hpp"

#include <shadow/error.hpp>

#include <algorithm>
#include <cmath>
#include <string>

namespace shadow {

using detail::coordinate_problem;
using detail::finite;
using detail::format_number;

void detail::check_light(const Light& light, const std::string& file, const std::string& path) {
  if (light.type == LightType::Directional) {
    if (!finite(light.to_light)) throw InputError({file, path + ".to_light"}, "direction is not finite");
    if (light.to_light == glm::dvec3(0.0)) throw InputError({file, path + ".to_light"}, "direction has zero length");
    // A direction's length does not matter (it is normalised safely for culling, exactly
    // elsewhere): any finite non-zero vector is accepted (tests/test_hard_cases.cpp).
  } else if (light.type == LightType::Point) {
    if (!finite(light.position)) throw InputError({file, path + ".position"}, "position is not finite");
    const std::string problem = coordinate_problem(light.position, "coordinate");
    if (!problem.empty()) throw InputError({file, path + ".position"}, "position has a " + problem);
  } else {
    throw InputError({file, path + ".type"}, "unknown light type");
  }
  if (!std::isfinite(light.intensity) || light.intensity < 0)
    throw InputError({file, path + ".intensity"},
                     "intensity must be finite and >= 0, got " + format_number(light.intensity));
  for (int c = 0; c < 3; ++c)
    if (!(light.color[c] >= 0.0 && light.color[c] <= 1.0))  // also catches NaN
      throw InputError({file, path + ".color"},
                       "color components must be in [0, 1], got " + format_number(light.color[c]));
}

std::vector<std::size_t> detail::resolve_lights(const Scene& scene, const std::vector<std::size_t>& requested) {
  std::vector<std::size_t> ids = requested;
  if (ids.empty())
    for (std::size_t l = 0; l < scene.lights.size(); ++l) ids.push_back(l);
  for (std::size_t i = 0; i < ids.size(); ++i)
    if (ids[i] >= scene.lights.size())
      throw InputError({"", "ShadowOptions::lights[" + std::to_string(i) + "]"},
                       "no light " + std::to_string(ids[i]) + ": the scene has " +
                           std::to_string(scene.lights.size()) + (scene.lights.size() == 1 ? " light" : " lights"));
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  for (std::size_t l : ids) check_light(scene.lights[l], scene.source.string(), "lights[" + std::to_string(l) + "]");
  return ids;
}

}  // namespace shadow
