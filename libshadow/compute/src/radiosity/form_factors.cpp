// SPDX-License-Identifier: GPL-3.0-or-later
// Face-to-face form factors with exact visibility (docs/radiosity.md): the point form factor to
// the source face (Lambert's contour over its visible part) integrated over the receiving face.
#include <shadow/radiosity.hpp>

#include "runtime/parallel.hpp"
#include "radiosity/shooter_view.hpp"
#include "radiosity/triangles.hpp"

#include <shadow/error.hpp>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <string>

namespace shadow {
namespace {

constexpr double kPi = 3.14159265358979323846;

void check_face(const Scene& scene, std::size_t face, const std::string& what) {
  if (face >= scene.faces.size())
    throw InputError({"", what}, "no face " + std::to_string(face) + ": the scene has " +
                                     std::to_string(scene.faces.size()) + " faces");
  const Face& f = scene.faces[face];
  if (f.degenerate || f.vertices.size() < 3 || radiosity::triangulate(f.vertices).empty())
    throw InputError({"", what}, "face " + std::to_string(face) + " has zero area");
}

}  // namespace

std::vector<double> point_form_factors(const Scene& scene, std::size_t to_face, const std::vector<SurfacePoint>& points,
                                       unsigned threads) {
  check_face(scene, to_face, "to_face");
  Light source;
  source.name = "face " + std::to_string(to_face);
  source.type = LightType::Area;
  source.polygon = scene.faces[to_face].vertices;
  source.intensity = 1.0 / kPi;  // the irradiance pi L F is then F
  return light_irradiance(scene, source, points, threads);
}

FormFactor form_factor(const Scene& scene, std::size_t from_face, std::size_t to_face,
                       const FormFactorOptions& options) {
  check_face(scene, from_face, "from_face");
  check_face(scene, to_face, "to_face");
  if (!(options.tolerance >= 0.0) || !std::isfinite(options.tolerance))
    throw InputError({"", "tolerance"}, "tolerance must be a finite number >= 0");
  if (options.max_order < 2 || options.max_order > 256)
    throw InputError({"", "max_order"}, "max_order must be in [2, 256], got " + std::to_string(options.max_order));
  FormFactor result;
  if (from_face == to_face) return result;  // a planar face does not see itself
  const std::vector<radiosity::Triangle> source = radiosity::triangulate(scene.faces[from_face].vertices);
  double from_area = 0.0;
  for (const radiosity::Triangle& t : source) from_area += radiosity::triangle_area(t);
  const std::vector<radiosity::Triangle> receiver = radiosity::triangulate(scene.faces[to_face].vertices);

  const unsigned n = runtime::resolve_threads(runtime::checked_threads(options.threads));
  radiosity::ShooterView view(scene, n);
  view.set_shooter(from_face, scene.faces[from_face].vertices);
  double previous = 0.0;
  for (int order = 2; order <= options.max_order; order *= 2) {
    std::vector<double> nodes, weights;
    radiosity::gauss_legendre01(order, nodes, weights);
    // Collapsed square on each triangle (a, b, c): y(u, v) = a + u (b - a) + u v (c - b),
    // dA = 2 area u du dv.
    std::vector<SurfacePoint> points;
    std::vector<double> w;
    for (const radiosity::Triangle& t : receiver) {
      const double twice = 2.0 * radiosity::triangle_area(t);
      for (int i = 0; i < order; ++i)
        for (int j = 0; j < order; ++j) {
          const double u = nodes[static_cast<std::size_t>(i)], v = nodes[static_cast<std::size_t>(j)];
          points.push_back({to_face, t[0] + u * (t[1] - t[0]) + u * v * (t[2] - t[1])});
          w.push_back(twice * u * weights[static_cast<std::size_t>(i)] * weights[static_cast<std::size_t>(j)]);
        }
    }
    std::vector<double> f(points.size(), 0.0);
    runtime::parallel_for(points.size(), n, [&](unsigned worker, std::size_t i) { f[i] = view.evaluate(worker, points[i]); });
    double sum = 0.0;
    for (std::size_t i = 0; i < f.size(); ++i) sum += w[i] * f[i];
    const double value = sum / from_area;
    result.evaluations += points.size();
    if (order > 2) {
      result.value = value;
      result.error = std::abs(value - previous);
      result.order = order;
      if (result.error <= options.tolerance * std::max(std::abs(value), std::abs(previous)) || result.error <= 1e-12)
        break;
    }
    previous = value;
  }
  return result;
}

}  // namespace shadow
