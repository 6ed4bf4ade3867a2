// SPDX-License-Identifier: GPL-3.0-or-later
// The scene's own reflections over a period (`shadow irradiance --reflections`, docs/irradiance.md):
// radiosity is linear in its sources, so one solution whose sources are the faces' irradiation
// summed over the period gives the period's reflected irradiation.
#include <shadow/irradiance.hpp>

#include <shadow/error.hpp>
#include <shadow/radiosity.hpp>

#include <chrono>
#include <cmath>
#include <string>

namespace shadow {

void add_scene_reflections(const Scene& scene, IrradianceResult& result, const ReflectionOptions& options) {
  if (!(options.default_reflectance >= 0.0) || !(options.default_reflectance < 1.0))
    throw InputError({"", "default_reflectance"}, "the reflectance of faces without one must be in [0, 1)");
  const auto start = std::chrono::steady_clock::now();
  // Faces whose material gives no reflectance reflect the default; ground faces reflect nothing
  // here: their reflection is the ground-reflected component already (the ground's albedo).
  RadiosityOptions ro;
  const std::vector<unsigned char> ground = ground_faces(scene);
  ro.face_reflectance.assign(scene.faces.size(), 0.0);
  for (std::size_t f = 0; f < scene.faces.size(); ++f) {
    const Material& m = scene.material_of(f);
    const bool has = m.reflectance > 0.0 || m.reflectance_rgb != glm::dvec3(0.0) || m.emittance > 0.0;
    ro.face_reflectance[f] = ground[f] != 0 ? 0.0 : has ? m.reflectance : options.default_reflectance;
  }
  // The sources: each receiving face's irradiation over the period (kWh/m2); other faces none.
  ro.face_irradiance.assign(scene.faces.size(), 0.0);
  for (std::size_t row = 0; row < result.faces.size(); ++row) ro.face_irradiance[result.faces[row]] = result.total[row];
  ro.max_element_area = options.max_element_area;
  ro.tolerance = options.tolerance;
  ro.threads = options.threads;
  ro.progress = options.progress;
  const RadiosityResult solution = solve_radiosity(scene, ro);
  result.scene_reflected.assign(result.faces.size(), 0.0);
  for (std::size_t row = 0; row < result.faces.size(); ++row) {
    const FaceRadiosity& f = solution.faces[result.faces[row]];
    // What arrives from the other faces: all incident minus the sources' own share.
    result.scene_reflected[row] = f.area > 0.0 ? std::max(0.0, f.irradiance - f.direct_irradiance) : 0.0;
    result.total[row] += result.scene_reflected[row];
  }
  result.reflections.elements = solution.elements.size();
  result.reflections.shots = solution.shots;
  result.reflections.unshot_fraction = solution.unshot_fraction;
  result.reflections.error_estimate = solution.error_estimate;
  result.reflections.hierarchical = solution.hierarchical;
  result.reflections.iterations = solution.iterations;
  result.reflections.near_links = solution.near_links;
  result.reflections.far_links = solution.far_links;
  result.reflections.default_reflectance = options.default_reflectance;
  result.reflections.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace shadow
