// SPDX-License-Identifier: GPL-3.0-or-later
// shadow-bench soft: speed against error of the soft-shadow baselines on scenes with an extended
// light. Every method estimates the visible fraction of the light at the same points (a grid on
// every receiving face); errors are against the exact fraction at those points, per point and, through
// soft_face_estimates, per face (fully-lit and umbra areas).
#include "bench_soft.hpp"

#include <shadow/area_lights.hpp>
#include <shadow/baselines.hpp>
#include <shadow/shadow.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <random>
#include <string>
#include <vector>

namespace bench {

namespace {

struct SoftScene {
  std::string name, light_text;
  shadow::Scene scene;
  shadow::Light light;
  double spacing = 0.1;  ///< point grid on the faces (m)
};

shadow::Light square_light(double side, glm::dvec3 centre) {
  shadow::Light l;
  l.name = "luminaire";
  l.type = shadow::LightType::Area;
  const double h = 0.5 * side;
  // Clockwise seen from above: the front faces down.
  l.polygon = {centre + glm::dvec3(-h, -h, 0), centre + glm::dvec3(-h, h, 0), centre + glm::dvec3(h, h, 0),
               centre + glm::dvec3(h, -h, 0)};
  return l;
}

/// A 1 m square luminaire 3 m over `boxes` boxes (0.4..1.2 m wide, 0.3..1.2 m high, seeded) on
/// a ground square of side `side`.
SoftScene luminaire_scene(std::size_t boxes, double side, double spacing) {
  SoftScene s;
  s.name = "luminaire";
  s.light_text = "square 1 m at 3 m";
  shadow::add_mesh(s.scene, "ground", {shadow::rectangle_z(-side / 2, -side / 2, side / 2, side / 2, 0)});
  std::mt19937_64 rng(2026);
  std::uniform_real_distribution<double> pos(-0.3 * side, 0.3 * side), width(0.4, 1.2), height(0.3, 1.2);
  std::vector<shadow::Polygon3> faces;
  for (std::size_t b = 0; b < boxes; ++b) {
    const double x = pos(rng), y = pos(rng), w = width(rng), d = width(rng), h = height(rng);
    for (const shadow::Polygon3& f : shadow::box_faces({x, y, 0}, {x + w, y + d, h})) faces.push_back(f);
  }
  shadow::add_mesh(s.scene, "boxes", faces);
  s.light = square_light(1.0, {0, 0, 3});
  s.spacing = spacing;
  return s;
}

/// The sun as a disk of 0.53 degrees, 40 degrees up, over a generated city.
SoftScene sun_city_scene(std::size_t boxes, double extent, double spacing) {
  SoftScene s;
  s.name = "sun-city";
  s.light_text = "sun disk 0.53 deg, 40 deg up";
  s.scene = shadow::make_city(boxes, extent, 2026);
  s.light = shadow::directional_light("sun", shadow::sun_direction(40.0, 135.0));
  s.light.angular_diameter = 0.53;
  s.spacing = spacing;
  return s;
}

/// The furnished room with its ceiling lamp made a disk of radius 0.25 m facing down.
SoftScene room_disk_scene(std::size_t tables, double spacing) {
  SoftScene s;
  s.name = "room-disk";
  s.light_text = "disk r 0.25 m, ceiling";
  s.scene = shadow::make_furnished_room(tables, 11);
  const glm::dvec3 lamp = s.scene.lights.at(0).position;
  s.scene.lights.clear();
  s.light.name = "disk";
  s.light.type = shadow::LightType::Disk;
  s.light.position = lamp;
  s.light.normal = {0, 0, -1};
  s.light.radius = 0.25;
  s.spacing = spacing;
  return s;
}

struct Run {
  std::string method, parameter_name;
  double parameter = 0;
  std::string setting;
  std::function<shadow::SoftResult(const SoftScene&, const std::vector<shadow::SurfacePoint>&, unsigned)> run;
};

struct PointErrors {
  double mean = 0, rms = 0, max = 0, penumbra_mean = 0;
  std::size_t penumbra_points = 0, out_of_range = 0;
};

PointErrors point_errors(const std::vector<double>& got, const std::vector<double>& ref) {
  PointErrors e;
  double sum = 0, sum2 = 0, pen = 0;
  for (std::size_t i = 0; i < ref.size(); ++i) {
    const double d = std::abs(got[i] - ref[i]);
    if (!(got[i] >= 0 && got[i] <= 1)) ++e.out_of_range;
    sum += d;
    sum2 += d * d;
    e.max = std::max(e.max, d);
    if (ref[i] > 0 && ref[i] < 1) {
      pen += d;
      ++e.penumbra_points;
    }
  }
  const double n = std::max<double>(1, static_cast<double>(ref.size()));
  e.mean = sum / n;
  e.rms = std::sqrt(sum2 / n);
  e.penumbra_mean = e.penumbra_points ? pen / static_cast<double>(e.penumbra_points) : 0.0;
  return e;
}

/// Per-face errors: sum over faces of |estimate - reference| of the lit (visibility-weighted),
/// fully-lit and umbra areas, over the faces' total area.
struct FaceErrors {
  double lit = 0, fully_lit = 0, umbra = 0;
  double region_fully_lit = 0, region_umbra = 0;  ///< against the exact regions (polygons)
};

FaceErrors face_errors(const std::vector<shadow::FaceLighting>& got, const std::vector<shadow::FaceLighting>& ref,
                       const std::vector<shadow::FaceLighting>& regions) {
  FaceErrors e;
  double area = 0;
  for (std::size_t k = 0; k < ref.size(); ++k) {
    area += ref[k].area;
    e.lit += std::abs(got[k].lit_area - ref[k].lit_area);
    e.fully_lit += std::abs(got[k].fully_lit_area - ref[k].fully_lit_area);
    e.umbra += std::abs(got[k].umbra_area - ref[k].umbra_area);
    e.region_fully_lit += std::abs(got[k].fully_lit_area - regions[k].fully_lit_area);
    e.region_umbra += std::abs(got[k].umbra_area - regions[k].umbra_area);
  }
  if (area > 0) {
    e.lit /= area;
    e.fully_lit /= area;
    e.umbra /= area;
    e.region_fully_lit /= area;
    e.region_umbra /= area;
  }
  return e;
}

/// The exact fully-lit, penumbra and umbra regions of every sampled face (the engine with the
/// light as the scene's only light, areas only), in the order of `pts.face_ids`.
std::vector<shadow::FaceLighting> exact_regions(const SoftScene& s, const shadow::FacePoints& pts, unsigned threads,
                                                double& seconds) {
  shadow::Scene scene = s.scene;
  scene.lights = {s.light};
  shadow::validate_scene(scene);
  shadow::ShadowOptions options;
  options.threads = threads;
  options.polygons = false;
  const auto t0 = std::chrono::steady_clock::now();
  const shadow::ShadowResult result = shadow::compute_shadows(scene, options);
  seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::vector<shadow::FaceLighting> out;
  for (std::size_t f : pts.face_ids) {
    const shadow::FaceLighting* fl = result.find(f, 0);
    out.push_back(fl ? *fl : shadow::FaceLighting{});
  }
  return out;
}

std::vector<Run> runs(bool quick) {
  std::vector<Run> out;
  const std::vector<int> resolutions = quick ? std::vector<int>{256} : std::vector<int>{256, 1024, 4096};
  const std::vector<int> radii = quick ? std::vector<int>{0, 2} : std::vector<int>{0, 1, 3, 8};
  for (int r : radii)
    for (int res : resolutions)
      out.push_back({"pcf-r" + std::to_string(r), "resolution", static_cast<double>(res),
                     "kernel " + std::to_string(2 * r + 1) + "^2 texels",
                     [r, res](const SoftScene& s, const std::vector<shadow::SurfacePoint>& p, unsigned threads) {
                       shadow::SoftShadowMapOptions o;
                       o.resolution = res;
                       o.pcf_radius = r;
                       o.threads = threads;
                       return shadow::pcf_visibility(s.scene, s.light, p, o);
                     }});
  for (int res : resolutions)
    out.push_back({"pcss", "resolution", static_cast<double>(res), "caps 64 texels, at most 17^2 taps",
                   [res](const SoftScene& s, const std::vector<shadow::SurfacePoint>& p, unsigned threads) {
                     shadow::SoftShadowMapOptions o;
                     o.resolution = res;
                     o.threads = threads;
                     return shadow::pcss_visibility(s.scene, s.light, p, o);
                   }});
  const std::vector<unsigned> ks = quick ? std::vector<unsigned>{4, 64} : std::vector<unsigned>{1, 4, 16, 64, 256};
  for (unsigned k : ks)
    out.push_back({"rays", "k", static_cast<double>(k), "stratified, seed 1",
                   [k](const SoftScene& s, const std::vector<shadow::SurfacePoint>& p, unsigned threads) {
                     shadow::SoftRayOptions o;
                     o.rays = k;
                     o.threads = threads;
                     return shadow::ray_visibility(s.scene, s.light, p, o);
                   }});
  return out;
}

}  // namespace

int run_soft(const SoftOptions& o) {
  std::vector<SoftScene> scenes;
  if (o.quick) {
    scenes.push_back(luminaire_scene(3, 4.0, 0.1));
  } else {
    scenes.push_back(luminaire_scene(6, 8.0, 0.05));
    scenes.push_back(sun_city_scene(20, 60.0, 0.4));
    scenes.push_back(room_disk_scene(4, 0.1));
  }
  const unsigned reference_rays = o.quick ? std::min(o.reference_rays, 1024u) : o.reference_rays;
  std::ofstream csv;
  if (!o.csv_path.empty()) {
    csv.open(o.csv_path);
    csv.precision(10);
    csv << "scene,light,faces,points,penumbra_points,method,parameter_name,parameter,setting,reference,threads,prepare_s,"
           "compute_s,total_s,lookups,map_mib,mean_abs_error,rms_error,max_abs_error,penumbra_mean_abs_error,"
           "lit_area_error,fully_lit_area_error,umbra_area_error,region_fully_lit_area_error,region_umbra_area_error,"
           "regions_s\n";
  }
  std::printf("| scene | points | method | parameter | total (s) | mean abs err | max abs err | penumbra mean err | "
              "lit area err | fully-lit area err | umbra area err | fully-lit err (regions) | umbra err (regions) |\n");
  std::printf("|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  int status = 0;
  for (SoftScene& s : scenes) {
    if (!o.only_scenes.empty() && std::find(o.only_scenes.begin(), o.only_scenes.end(), s.name) == o.only_scenes.end())
      continue;
    shadow::validate_scene(s.scene);
    const shadow::FacePoints pts = shadow::face_sample_points(s.scene, s.spacing);
    // The reference: the exact visible fraction (light_visibility), timed like the others.
    const std::string reference = "exact light_visibility";
    shadow::SoftResult ref;
    {
      const auto t0 = std::chrono::steady_clock::now();
      ref.visibility = shadow::light_visibility(s.scene, s.light, pts.points, o.threads);
      ref.compute_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    }
    const std::vector<shadow::FaceLighting> ref_faces = shadow::soft_face_estimates(pts, ref.visibility, 0);
    double region_seconds = 0;
    const std::vector<shadow::FaceLighting> regions = exact_regions(s, pts, o.threads, region_seconds);
    std::vector<Run> all = runs(o.quick);
    all.insert(all.begin(), Run{"exact", "", 0, reference, nullptr});
    // The cross-check: k rays with a very large k must agree with the exact fractions.
    all.push_back(Run{"rays-reference", "k", static_cast<double>(reference_rays), "stratified, seed 12345",
                      [reference_rays](const SoftScene& sc, const std::vector<shadow::SurfacePoint>& p, unsigned threads) {
                        shadow::SoftRayOptions ro;
                        ro.rays = reference_rays;
                        ro.threads = threads;
                        ro.seed = 12345;
                        return shadow::ray_visibility(sc.scene, sc.light, p, ro);
                      }});
    std::vector<std::pair<double, double>> ray_errors;  // (k, mean error)
    for (const Run& r : all) {
      const shadow::SoftResult got = r.run ? r.run(s, pts.points, o.threads) : ref;
      const PointErrors pe = point_errors(got.visibility, ref.visibility);
      const FaceErrors fe = face_errors(shadow::soft_face_estimates(pts, got.visibility, 0), ref_faces, regions);
      if (pe.out_of_range) status = 1;
      if (r.method == "rays" || r.method == "rays-reference") ray_errors.emplace_back(r.parameter, pe.mean);
      const double total = got.prepare_seconds + got.compute_seconds;
      std::printf("| %s | %zu | %s | %g | %.3f | %.2e | %.2e | %.2e | %.2e | %.2e | %.2e | %.2e | %.2e |\n",
                  s.name.c_str(), pts.points.size(), r.method.c_str(), r.parameter, total, pe.mean, pe.max,
                  pe.penumbra_mean, fe.lit, fe.fully_lit, fe.umbra, fe.region_fully_lit, fe.region_umbra);
      std::fflush(stdout);
      if (csv.is_open())
        csv << s.name << ",\"" << s.light_text << "\"," << s.scene.faces.size() << ',' << pts.points.size() << ','
            << pe.penumbra_points << ',' << r.method << ',' << r.parameter_name << ',' << r.parameter << ",\""
            << r.setting << "\",\"" << reference << "\"," << o.threads << ',' << got.prepare_seconds << ','
            << got.compute_seconds << ',' << total << ',' << got.lookups << ','
            << static_cast<double>(got.map_bytes) / (1024.0 * 1024.0) << ',' << pe.mean << ',' << pe.rms << ','
            << pe.max << ',' << pe.penumbra_mean << ',' << fe.lit << ',' << fe.fully_lit << ',' << fe.umbra << ','
            << fe.region_fully_lit << ',' << fe.region_umbra << ',' << region_seconds << '\n';
    }
    if (o.max_error >= 0 && ray_errors.size() >= 2) {
      const double first = ray_errors.front().second, last = ray_errors.back().second;
      if (!(last < first) || last > o.max_error) {
        std::fprintf(stderr, "shadow-bench soft: %s: rays' mean error %.3g at k=%g (%.3g at k=%g), limit %.3g\n",
                     s.name.c_str(), last, ray_errors.back().first, first, ray_errors.front().first, o.max_error);
        status = 1;
      }
    }
  }
  std::printf(status == 0 ? "soft: checks passed\n" : "soft: checks FAILED\n");
  return status;
}

}  // namespace bench
