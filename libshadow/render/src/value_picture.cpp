// SPDX-License-Identifier: GPL-3.0-or-later
// Pictures of a value per face (docs/render.md, "Irradiation"): the faces are cut into convex
// cells by the same exact overlay the shaded pictures use (one whole, lit "fragment" per face),
// each cell flat in its face's colour, and drawn with the legend of the scale.
#include <shadow/render/value_picture.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace shadow::render {
namespace {

/// sRGB (0-1) to linear: the mesh holds linear colours, which render_mesh encodes back.
double linear(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }

}  // namespace

glm::dvec3 linear_from_srgb(const glm::dvec3& srgb) { return {linear(srgb.r), linear(srgb.g), linear(srgb.b)}; }

glm::dvec3 srgb_from_linear(const glm::dvec3& linear) {
  glm::dvec3 out;
  for (int i = 0; i < 3; ++i) {
    const double x = std::clamp(linear[i], 0.0, 1.0);
    out[i] = x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055;
  }
  return out;
}

ValueScale value_scale(const std::vector<double>& values) {
  double most = 0.0;
  for (double v : values)
    if (std::isfinite(v)) most = std::max(most, v);
  ValueScale scale;
  if (!(most > 0.0)) return scale;
  // A round step (1, 2 or 5 times a power of ten) that gives at most 8 labels from 0 to the top.
  const double base = std::pow(10.0, std::floor(std::log10(most / 7.0)));
  scale.step = 10.0 * base;
  for (double factor : {1.0, 2.0, 5.0, 10.0})
    if (most / (factor * base) <= 7.0) {
      scale.step = factor * base;
      break;
    }
  scale.top = scale.step * std::max(1.0, std::ceil(most / scale.step - 1e-9));
  scale.digits = scale.step >= 1.0 ? 0 : static_cast<int>(std::ceil(-std::log10(scale.step) - 1e-9));
  return scale;
}

glm::dvec3 value_colour(double t) {
  // Control colours chosen here (sRGB): each brighter than the one before.
  static const glm::dvec3 stops[] = {{0.06, 0.03, 0.20}, {0.36, 0.08, 0.46}, {0.74, 0.20, 0.32},
                                     {0.96, 0.52, 0.12}, {0.99, 0.94, 0.62}};
  constexpr int last = 4;
  const double x = std::clamp(std::isfinite(t) ? t : 0.0, 0.0, 1.0) * last;
  const int i = std::min(static_cast<int>(x), last - 1);
  const double f = x - i;
  return stops[i] * (1.0 - f) + stops[i + 1] * f;
}

ColouredMesh colour_faces_by_value(const Scene& scene, const std::vector<double>& values, const ValueScale& scale) {
  // Each face one lit fragment of one light: the overlay then gives its convex cells.
  Scene one_light = scene;
  one_light.lights.assign(1, Light{});
  ShadowResult whole;
  for (std::size_t f = 0; f < scene.faces.size(); ++f) {
    if (scene.faces[f].degenerate) continue;
    Fragment fragment;
    fragment.face_id = f;
    fragment.lit = true;
    fragment.polygon = scene.faces[f].vertices;
    whole.fragments.push_back(std::move(fragment));
  }
  ColouredMesh mesh;
  for (const OverlayCell& cell : overlay_fragments(one_light, whole)) {
    const double v = cell.face_id < values.size() ? values[cell.face_id] : std::nan("");
    const glm::dvec3 colour =
        linear_from_srgb(std::isfinite(v) ? value_colour(v / scale.top) : glm::dvec3(kNoValueGrey, kNoValueGrey, kNoValueGrey * 0.98));
    const std::size_t first = mesh.points.size();
    mesh.points.insert(mesh.points.end(), cell.polygon.begin(), cell.polygon.end());
    for (std::size_t k = 1; k + 1 < cell.polygon.size(); ++k) {  // convex: a fan
      mesh.triangles.insert(mesh.triangles.end(), {first, first + k, first + k + 1});
      mesh.triangle_colours.push_back(colour);
    }
  }
  return mesh;
}

Decorations value_decorations(const Scene& scene, const ValueScale& scale, const RenderOptions& options,
                              const std::string& title) {
  Decorations d;
  d.header = title;
  const int labels = static_cast<int>(std::lround(scale.top / scale.step));
  for (int k = labels; k >= 0; --k) {
    LegendEntry entry;
    char text[64];
    std::snprintf(text, sizeof text, "%.*f", scale.digits, k * scale.step);
    entry.label = text;
    entry.lit = entry.shadow = value_colour(k * scale.step / scale.top);
    d.legend.push_back(entry);
  }
  if (options.compass) {
    RenderOptions compass_only = options;
    compass_only.legend = false;
    Scene no_lights = scene;
    no_lights.lights.clear();
    const Decorations c = make_decorations(no_lights, compass_only, 1.0);
    d.compass = c.compass;
    d.anchor = c.anchor;
    d.north = c.north;
  }
  return d;
}

Image render_face_values(const Scene& scene, const std::vector<double>& values, const RenderOptions& options,
                         const std::string& title) {
  const ValueScale scale = value_scale(values);
  const ColouredMesh mesh = colour_faces_by_value(scene, values, scale);
  Decorations d = value_decorations(scene, scale, options, title);
  bool any_missing = false;
  for (std::size_t f = 0; f < scene.faces.size(); ++f)
    any_missing = any_missing || (!scene.faces[f].degenerate && !(f < values.size() && std::isfinite(values[f])));
  if (any_missing) d.notes.push_back("grey: faces without a value");
  Image image = render_mesh(mesh, options, d);
  return image;
}

}  // namespace shadow::render
