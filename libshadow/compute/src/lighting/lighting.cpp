// SPDX-License-Identifier: GPL-3.0-or-later
// The lighting models of the seed lecture notes (docs/lighting.md cites each equation).
#include <shadow/lighting.hpp>

#include "geometry/newell_normal.hpp"
#include "geometry/unit_vector.hpp"
#include "lighting/fragment_irradiance.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace shadow {
namespace {

using geometry::unit_or_zero;  // v / |v|, or zero when v has no usable direction

/// Newell's normal of a polygon, unit length (zero for a polygon without area).
glm::dvec3 polygon_normal(const std::vector<glm::dvec3>& polygon) {
  return unit_or_zero(geometry::newell_normal(polygon));
}

bool uses_specular(LightingModel model) {
  return model == LightingModel::Phong || model == LightingModel::BlinnPhong;
}

/// Area lights and disks light as their centre (centre_light), a point light.
bool needs_centre(const Light& light) { return light.type == LightType::Area || light.type == LightType::Disk; }

}  // namespace

glm::dvec3 direction_to_light(const Light& light, const glm::dvec3& point) {
  if (needs_centre(light)) return direction_to_light(centre_light(light), point);
  if (light.type == LightType::Directional) return unit_or_zero(light.to_light);
  return unit_or_zero(light.position - point);
}

namespace {
/// Whether `point` lies on the side an area light or disk shines to (strictly in front of the
/// plane through its centre): behind it, nothing of the light arrives.
bool on_emitting_side(const Light& light, const glm::dvec3& point, const glm::dvec3& centre) {
  const glm::dvec3 front = light.type == LightType::Disk ? light.normal : geometry::newell_normal(light.polygon);
  return glm::dot(front, point - centre) > 0.0;
}
}  // namespace

double irradiance(const Light& light, const glm::dvec3& point, const glm::dvec3& normal) {
  if (needs_centre(light)) {
    const Light centre = centre_light(light);
    return on_emitting_side(light, point, centre.position) ? irradiance(centre, point, normal) : 0.0;
  }
  const glm::dvec3 l = direction_to_light(light, point);
  const double cosine = std::max(0.0, glm::dot(unit_or_zero(normal), l));
  if (light.type == LightType::Directional) return light.intensity * cosine;
  const glm::dvec3 offset = light.position - point;
  const double r2 = glm::dot(offset, offset);
  if (!(r2 > 0.0)) return 0.0;  // the lamp sits on the point: no direction, no finite answer
  return light.intensity * cosine / r2;
}

void detail::fragment_irradiance(const Scene& scene, const Fragment& fragment, double* out) {
  const bool known_light = fragment.light_id < scene.lights.size();
  const glm::dvec3 normal = fragment.face_id < scene.faces.size()
                                ? polygon_normal(scene.faces[fragment.face_id].vertices)
                                : polygon_normal(fragment.polygon);
  for (const glm::dvec3& p : fragment.polygon) {
    double value = std::numeric_limits<double>::quiet_NaN();
    if (known_light) value = fragment.lit ? irradiance(scene.lights[fragment.light_id], p, normal) : 0.0;
    *out++ = value;
  }
}

double attenuation_factor(const Light& light, const glm::dvec3& position, const glm::dvec3& viewer,
                          const LightingSettings& settings) {
  if (needs_centre(light)) return attenuation_factor(centre_light(light), position, viewer, settings);
  const bool point_light = light.type == LightType::Point;
  switch (settings.attenuation) {
    case Attenuation::None:
      return 1.0;
    case Attenuation::InverseSquare: {
      if (!point_light) return 1.0;  // the sun is equally far from every point of a scene
      const glm::dvec3 offset = light.position - position;
      const double r2 = glm::dot(offset, offset);
      return r2 > 0.0 ? 1.0 / r2 : 0.0;
    }
    case Attenuation::ViewerLinear:
    case Attenuation::LightLinear: {
      double d = 0.0;
      if (settings.attenuation == Attenuation::ViewerLinear) d = glm::length(viewer - position);
      else if (point_light) d = glm::length(light.position - position);
      else return 1.0;
      const double denominator = d + settings.attenuation_k;
      return denominator > 0.0 ? 1.0 / denominator : 0.0;
    }
  }
  return 1.0;
}

glm::dvec3 shade(const ShadingPoint& point, const Material& m, const std::vector<Light>& lights,
                 const std::vector<bool>& lit, const LightingSettings& settings) {
  // Seed 000: I_a = k_a i_a, the same at every point, shadow or not.
  glm::dvec3 colour = m.k_a * settings.ambient_intensity * settings.ambient_color * m.color;
  if (settings.model == LightingModel::Ambient) return colour;

  glm::dvec3 n = unit_or_zero(point.normal);
  const glm::dvec3 v = unit_or_zero(point.viewer - point.position);
  // Only the front of a face can be lit (the scene contract). A viewer behind the face sees its
  // back: the visible side's normal is -n, and no scene light reaches it (attached shadow).
  const bool seen_from_behind = glm::dot(n, v) < 0.0;
  if (seen_from_behind) n = -n;
  const glm::dvec3 diffuse_reflectance = m.k_d * m.color;           // M_D
  const glm::dvec3 specular_reflectance = m.k_s * m.specular_color;  // M_S

  for (std::size_t j = 0; j < lights.size(); ++j) {
    const Light& light = lights[j];
    const bool reaches = !seen_from_behind && (j >= lit.size() || lit[j]);
    const glm::dvec3 l = direction_to_light(light, point.position);
    const double n_dot_l = glm::dot(n, l);
    const double falloff = attenuation_factor(light, point.position, point.viewer, settings);
    const glm::dvec3 incoming = light.intensity * light.color;  // I C_L

    glm::dvec3 term(0.0);
    switch (settings.model) {
      case LightingModel::Ambient:
        break;
      case LightingModel::Lambert:
      case LightingModel::Phong:
      case LightingModel::BlinnPhong:
        if (reaches) term += incoming * diffuse_reflectance * std::max(0.0, n_dot_l);
        break;
      case LightingModel::HalfLambert:
        // Seed 003: N.L mapped from [-1, 1] to [0, 1].
        if (reaches) term += incoming * diffuse_reflectance * (0.5 * n_dot_l + 0.5);
        break;
      case LightingModel::ModifiedHalfLambert: {
        // Seed 003: C_D = I_F C_LF M_D H + I_B C_LB M_D (1 - H), H = 0.5 N.L + 0.5. The front
        // light is the scene light (and only it can be shadowed); the back light is a fill.
        const double h = 0.5 * n_dot_l + 0.5;
        if (reaches) term += incoming * diffuse_reflectance * h;
        term += settings.back_intensity * settings.back_color * diffuse_reflectance * (1.0 - h);
        break;
      }
    }

    // Highlights only where the light arrives on the front side.
    if (uses_specular(settings.model) && reaches && n_dot_l > 0.0) {
      double cosine = 0.0;
      if (settings.model == LightingModel::Phong) {
        const glm::dvec3 r = 2.0 * n_dot_l * n - l;  // seed 003: R = 2N(N.L) - L
        cosine = std::max(0.0, glm::dot(r, v));
      } else {
        const glm::dvec3 h = unit_or_zero(l + v);  // seed 003: H = (V + L) / |V + L|
        cosine = std::max(0.0, glm::dot(n, h));
      }
      term += incoming * specular_reflectance * std::pow(cosine, m.shininess);
    }
    colour += falloff * term;
  }
  return colour;
}

std::string to_string(LightingModel model) {
  switch (model) {
    case LightingModel::Ambient: return "ambient";
    case LightingModel::Lambert: return "lambert";
    case LightingModel::HalfLambert: return "half-lambert";
    case LightingModel::ModifiedHalfLambert: return "modified-half-lambert";
    case LightingModel::Phong: return "phong";
    case LightingModel::BlinnPhong: return "blinn-phong";
  }
  return "?";
}

std::string to_string(Attenuation attenuation) {
  switch (attenuation) {
    case Attenuation::None: return "none";
    case Attenuation::InverseSquare: return "inverse-square";
    case Attenuation::ViewerLinear: return "viewer-linear";
    case Attenuation::LightLinear: return "light-linear";
  }
  return "?";
}

bool parse_lighting_model(const std::string& name, LightingModel& model) {
  for (LightingModel m : {LightingModel::Ambient, LightingModel::Lambert, LightingModel::HalfLambert,
                          LightingModel::ModifiedHalfLambert, LightingModel::Phong,
                          LightingModel::BlinnPhong}) {
    if (to_string(m) == name) {
      model = m;
      return true;
    }
  }
  return false;
}

bool parse_attenuation(const std::string& name, Attenuation& attenuation) {
  for (Attenuation a : {Attenuation::None, Attenuation::InverseSquare, Attenuation::ViewerLinear,
                        Attenuation::LightLinear}) {
    if (to_string(a) == name) {
      attenuation = a;
      return true;
    }
  }
  return false;
}

}  // namespace shadow
