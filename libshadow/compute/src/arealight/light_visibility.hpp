// SPDX-License-Identifier: GPL-3.0-or-later
// Internal: the visible fraction and the irradiance of an extended light at points, in one pass
// (light_visibility.cpp). No CGAL here.
#pragma once

#include <shadow/area_lights.hpp>

#include <cstddef>
#include <memory>
#include <utility>
#include <vector>

namespace shadow::detail {

/// Sum over the edges of a closed 3D polygon (its vertices relative to a point x) of
/// angle(r_a, r_b) (r_a x r_b) / |r_a x r_b| . n: twice the integral of cos cos' / r^2 over the
/// polygon, with a sign set by its orientation (Lambert's formula for the form factor): -1/(2 pi)
/// times it is the form factor from x (normal n) to a polygon counter-clockwise seen from x.
double lambert_contour(const std::vector<glm::dvec3>& r, const glm::dvec3& n);

/// The scene prepared once for many extended lights and points (radiosity shoots from many
/// elements): the exact faces are built once per worker and kept across lights.
class LightQuery {
 public:
  /// `workers`: how many threads may call evaluate at once (each with its own index).
  LightQuery(const Scene& scene, unsigned workers);
  ~LightQuery();
  LightQuery(const LightQuery&) = delete;
  LightQuery& operator=(const LightQuery&) = delete;
  /// The light the next evaluations are for. @throws InputError for an unusable light.
  void set_light(const Light& light, bool irradiance);
  /// (visible fraction, irradiance) at `point` (face_id and position checked by the caller), as
  /// light_visibility_irradiance. Distinct workers may call it concurrently.
  std::pair<double, double> evaluate(unsigned worker, const SurfacePoint& point,
                                     const glm::dvec3& toward = glm::dvec3(0.0)) const;
  unsigned workers() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// For each point: (visible fraction, irradiance); the irradiance is computed only when
/// `irradiance` is true (0 otherwise). `toward[i]`, where given and non-zero, is a direction
/// along point i's face: the values are then the limits from that side (they differ from the
/// point's own only where a face passes through the point: a contact edge). Errors as
/// light_visibility.
std::vector<std::pair<double, double>> light_visibility_irradiance(const Scene& scene, const Light& light,
                                                                   const std::vector<SurfacePoint>& points,
                                                                   unsigned threads, bool irradiance,
                                                                   const std::vector<glm::dvec3>& toward = {});

/// Sets Fragment::visibility and Fragment::irradiance of the fragments in `fragments` whose
/// light_id is `light_id` (`light`, extended), in one batch over all their vertices on `threads`
/// threads; other fragments are left as they are.
void fill_light_fragment_visibility(const Scene& scene, const Light& light, std::size_t light_id,
                                    std::vector<Fragment>& fragments, unsigned threads);

}  // namespace shadow::detail
