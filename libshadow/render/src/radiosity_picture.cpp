// SPDX-License-Identifier: GPL-3.0-or-later
// Pictures of a radiosity result (radiosity_picture.hpp): element values on the value scale or
// in colour, flat or averaged at shared vertices (Gouraud), drawn from the fronts only.
#include <shadow/render/radiosity_picture.hpp>

#include <shadow/error.hpp>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <tuple>

namespace shadow::render {
namespace {

/// Colour mode's legend: each material's wall colour (its RGB reflectance, as displayed) and
/// what the colours mean.
void add_colour_legend(const Scene& scene, const RadiosityFiles& files, double exposure, Decorations& d) {
  d.header = "colour: reflectance x irradiance";
  std::vector<std::string> seen;
  for (std::size_t i = 0; i < files.elements.size() && d.legend.size() < 8; ++i) {
    const std::size_t face = files.elements[i].face_id;
    const std::string name = face < scene.faces.size() ? scene.material_of(face).name : std::string();
    if (std::find(seen.begin(), seen.end(), name) != seen.end()) continue;
    seen.push_back(name);
    LegendEntry entry;
    entry.label = name.empty() ? "(no material)" : name;
    entry.lit = entry.shadow = srgb_from_linear(files.reflectance_rgb[i]);
    d.legend.push_back(entry);
  }
  char line[96];
  std::snprintf(line, sizeof line, "exposure %.3g per W/m\u00b2", exposure);
  d.notes.emplace_back(line);
}

}  // namespace

RadiosityMode parse_radiosity_mode(const std::string& text) {
  if (text == "radiosity") return RadiosityMode::Radiosity;
  if (text == "irradiance") return RadiosityMode::Irradiance;
  if (text == "colour" || text == "color") return RadiosityMode::Colour;
  throw InputError({"", "--radiosity-mode"}, "expected radiosity, irradiance or colour, got \"" + text + "\"");
}

std::vector<glm::dvec3> radiosity_element_values(const RadiosityFiles& files, RadiosityMode mode) {
  std::vector<glm::dvec3> values(files.elements.size());
  for (std::size_t i = 0; i < files.elements.size(); ++i) {
    const RadiosityElement& e = files.elements[i];
    switch (mode) {
      case RadiosityMode::Radiosity: values[i] = glm::dvec3(e.radiosity); break;
      case RadiosityMode::Irradiance: values[i] = glm::dvec3(e.irradiance); break;
      // Each channel's irradiance (the solver's colour channels: colour bleeding) times the
      // channel's reflectance, plus the emittance (white).
      case RadiosityMode::Colour: values[i] = glm::dvec3(e.emittance) + files.reflectance_rgb[i] * e.irradiance_rgb; break;
    }
  }
  return values;
}

namespace {

/// `polygon` with the vertices of `others` that lie inside its edges inserted, in order along
/// them: where the refinement left a T-junction (a neighbour's vertex on this element's edge),
/// the two sides then meet vertex to vertex and the rasteriser leaves no crack between them.
std::vector<glm::dvec3> conforming_outline(const std::vector<glm::dvec3>& polygon, const std::vector<glm::dvec3>& others) {
  std::vector<glm::dvec3> out;
  for (std::size_t k = 0; k < polygon.size(); ++k) {
    const glm::dvec3 a = polygon[k], d = polygon[(k + 1) % polygon.size()] - a;
    out.push_back(a);
    const double dd = glm::dot(d, d);
    if (!(dd > 0.0)) continue;
    std::vector<std::pair<double, glm::dvec3>> on;
    for (const glm::dvec3& p : others) {
      const double t = glm::dot(p - a, d) / dd;
      // Inside the edge, off it by at most 1e-9 of its length (bisection midpoints are rounded).
      if (t > 1e-9 && t < 1.0 - 1e-9 && glm::length(p - (a + t * d)) <= 1e-9 * std::sqrt(dd)) on.emplace_back(t, p);
    }
    std::sort(on.begin(), on.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
    for (const auto& [t, p] : on) out.push_back(p);
  }
  return out;
}

}  // namespace

ColouredMesh radiosity_value_mesh(const RadiosityFiles& files, const std::vector<glm::dvec3>& values, bool smooth) {
  ColouredMesh mesh;
  // Each face's distinct vertices (bit-equal ones once: the solver's elements of one face share
  // theirs) and, smooth, one point each with the sums of area x value and of area over the
  // elements that have it as a corner.
  std::map<std::tuple<std::size_t, double, double, double>, std::size_t> shared;
  std::map<std::size_t, std::vector<glm::dvec3>> face_vertices;
  std::vector<double> weight;
  for (std::size_t i = 0; i < files.elements.size(); ++i) {
    const RadiosityElement& e = files.elements[i];
    for (const glm::dvec3& v : e.polygon) {
      const auto [it, added] = shared.try_emplace({e.face_id, v.x, v.y, v.z}, shared.size());
      if (added) {
        face_vertices[e.face_id].push_back(v);
        if (smooth) {
          mesh.points.push_back(v);
          mesh.point_colours.emplace_back(0.0);
          weight.push_back(0.0);
        }
      }
      if (!smooth) continue;
      // A degenerate element still counts, a little, so that no vertex is left without a value.
      const double w = std::max(e.area, 1e-300);
      mesh.point_colours[it->second] += w * values[i];
      weight[it->second] += w;
    }
  }
  for (std::size_t p = 0; p < mesh.point_colours.size(); ++p) mesh.point_colours[p] /= weight[p];
  auto point_id = [&](std::size_t face, const glm::dvec3& v) -> std::size_t {
    if (smooth) return shared.at({face, v.x, v.y, v.z});
    mesh.points.push_back(v);
    return mesh.points.size() - 1;
  };
  for (std::size_t i = 0; i < files.elements.size(); ++i) {
    const RadiosityElement& e = files.elements[i];
    const std::vector<glm::dvec3> outline = conforming_outline(e.polygon, face_vertices[e.face_id]);
    std::vector<std::size_t> ids;
    for (const glm::dvec3& v : outline) ids.push_back(point_id(e.face_id, v));
    if (outline.size() == e.polygon.size()) {
      for (std::size_t k = 1; k + 1 < ids.size(); ++k) {  // elements are triangles (convex): a fan
        mesh.triangles.insert(mesh.triangles.end(), {ids[0], ids[k], ids[k + 1]});
        if (!smooth) mesh.triangle_colours.push_back(values[i]);
      }
      continue;
    }
    // T-junctions on its edges: a fan from its centroid, whose smooth value is the mean of its
    // corners' (what Gouraud interpolation gives there).
    glm::dvec3 centroid(0.0), value(0.0);
    for (const glm::dvec3& v : e.polygon) {
      centroid += v / static_cast<double>(e.polygon.size());
      if (smooth) value += mesh.point_colours[point_id(e.face_id, v)] / static_cast<double>(e.polygon.size());
    }
    const std::size_t c = mesh.points.size();
    mesh.points.push_back(centroid);
    if (smooth) mesh.point_colours.push_back(value);
    for (std::size_t k = 0; k < ids.size(); ++k) {
      mesh.triangles.insert(mesh.triangles.end(), {c, ids[k], ids[(k + 1) % ids.size()]});
      if (!smooth) mesh.triangle_colours.push_back(values[i]);
    }
  }
  return mesh;
}

double radiosity_auto_exposure(const std::vector<glm::dvec3>& colours) {
  if (colours.empty()) return 1.0;
  std::vector<double> brightest(colours.size());
  for (std::size_t i = 0; i < colours.size(); ++i)
    brightest[i] = std::max({colours[i].r, colours[i].g, colours[i].b});
  const auto nth = brightest.begin() + static_cast<std::ptrdiff_t>(0.99 * static_cast<double>(brightest.size() - 1));
  std::nth_element(brightest.begin(), nth, brightest.end());
  return *nth > 0.0 && std::isfinite(*nth) ? 0.85 / *nth : 1.0;
}

Image render_radiosity(const Scene& scene, const RadiosityFiles& files, const RenderOptions& options,
                       const RadiosityPictureOptions& picture) {
  const std::vector<glm::dvec3> values = radiosity_element_values(files, picture.mode);
  ColouredMesh mesh = radiosity_value_mesh(files, values, picture.smooth);
  std::vector<glm::dvec3>& colours = picture.smooth ? mesh.point_colours : mesh.triangle_colours;
  RenderOptions adjusted = options;
  adjusted.cull_back_faces = true;
  Decorations d;
  if (picture.mode == RadiosityMode::Colour) {
    const Exposure& exposure = options.shade.exposure;
    double scale = exposure.scale;
    if (exposure.automatic) scale *= radiosity_auto_exposure(values);  // the elements, not the points
    for (glm::dvec3& c : colours) c = expose(c, exposure, scale);
    mesh.exposure = scale;
    if (options.legend) add_colour_legend(scene, files, scale, d);
    if (options.compass) {
      const Decorations c = value_decorations(scene, ValueScale{}, options, "");
      d.compass = c.compass;
      d.anchor = c.anchor;
      d.north = c.north;
    }
  } else {
    std::vector<double> plain(values.size());
    for (std::size_t i = 0; i < values.size(); ++i) plain[i] = values[i].r;
    const ValueScale scale = value_scale(plain);
    for (glm::dvec3& c : colours) c = linear_from_srgb(value_colour(c.r / scale.top));
    adjusted.legend = true;
    d = value_decorations(scene, scale, adjusted,
                          picture.mode == RadiosityMode::Radiosity ? "radiosity, W/m\u00b2" : "irradiance, W/m\u00b2");
  }
  Image image = render_mesh(mesh, adjusted, d);
  image.exposure = mesh.exposure;
  return image;
}

}  // namespace shadow::render
