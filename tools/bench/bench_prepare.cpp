// SPDX-License-Identifier: GPL-3.0-or-later
// shadow-bench prepare (bench_prepare.hpp).
#include "bench_prepare.hpp"

#include "core/face_prep.hpp"
#include "runtime/parallel.hpp"
#include "exact/convex_solids.hpp"
#include "validation/validate_reference.hpp"

#include <shadow/generators.hpp>
#include <shadow/scene_io.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <string>

// exact/exact_faces.hpp declares it but brings in CGAL's kernel; the bench needs only this.
namespace shadow::exact {
core::FacePrep prepare_face(const std::vector<glm::dvec3>& vertices);
}

namespace bench {
namespace {

double seconds_of(const std::function<void()>& work) {
  const auto t0 = std::chrono::steady_clock::now();
  work();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

bool same_faces(const shadow::Scene& a, const shadow::Scene& b) {
  if (a.faces.size() != b.faces.size() || a.warnings.size() != b.warnings.size()) return false;
  for (std::size_t f = 0; f < a.faces.size(); ++f)
    if (a.faces[f].vertices != b.faces[f].vertices || a.faces[f].degenerate != b.faces[f].degenerate) return false;
  for (std::size_t w = 0; w < a.warnings.size(); ++w)
    if (a.warnings[w].to_string() != b.warnings[w].to_string()) return false;
  return true;
}

std::vector<std::string> texts(const std::vector<shadow::Warning>& warnings) {
  std::vector<std::string> out;
  for (const shadow::Warning& w : warnings) out.push_back(w.to_string());
  return out;
}

bool same_solids(const std::vector<shadow::core::ConvexSolid>& a, const std::vector<int>& a_of,
                 const std::vector<shadow::core::ConvexSolid>& b, const std::vector<int>& b_of) {
  if (a.size() != b.size() || a_of != b_of) return false;
  for (std::size_t s = 0; s < a.size(); ++s)
    if (a[s].vertices != b[s].vertices || a[s].edges != b[s].edges) return false;
  return true;
}

/// Writes the faces of `mesh` as a Wavefront OBJ file, corners shared where their coordinates
/// are the same (a box's 8 corners), 17 significant digits so that they read back exactly.
void write_obj(const shadow::Scene& scene, std::size_t mesh, const std::filesystem::path& path) {
  std::ofstream out(path);
  out.precision(17);
  std::map<std::array<double, 3>, std::size_t> index;
  std::string faces;
  const shadow::Mesh& m = scene.meshes[mesh];
  for (std::size_t f = m.first_face; f < m.first_face + m.face_count; ++f) {
    faces += 'f';
    for (const glm::dvec3& v : scene.faces[f].vertices) {
      const auto [it, added] = index.try_emplace({v.x, v.y, v.z}, index.size() + 1);
      if (added) out << "v " << v.x << ' ' << v.y << ' ' << v.z << '\n';
      faces += ' ' + std::to_string(it->second);
    }
    faces += '\n';
    if (faces.size() > (1u << 20)) {
      // Flushed in blocks: the faces come after every vertex they name, and a block's
      // vertices were all written before it.
      out << faces;
      faces.clear();
    }
  }
  out << faces;
}

}  // namespace

int write_city(std::size_t boxes, double elevation, bool ground_only, const std::string& dir) {
  const double extent = 500.0 * std::sqrt(static_cast<double>(boxes) / 1000.0);
  const shadow::Scene city = shadow::make_city(boxes, extent, 2026);
  std::filesystem::create_directories(dir);
  for (std::size_t m = 0; m < city.meshes.size(); ++m)
    write_obj(city, m, std::filesystem::path(dir) / (city.meshes[m].name + ".obj"));
  const glm::dvec3 to_light = shadow::sun_direction(elevation, 135.0);
  std::ofstream scene(std::filesystem::path(dir) / "scene.json");
  scene.precision(17);
  scene << "{\n  \"meshes\": [";
  for (std::size_t m = 0; m < city.meshes.size(); ++m)
    scene << (m ? ", " : "") << "{\"name\": \"" << city.meshes[m].name << "\", \"file\": \"" << city.meshes[m].name
          << ".obj\"}";
  scene << "],\n  \"lights\": [{\"name\": \"sun\", \"type\": \"directional\", \"to_light\": [" << to_light.x
        << ", " << to_light.y << ", " << to_light.z << "]}]";
  if (ground_only) scene << ",\n  \"receivers\": [\"ground\"]";
  scene << "\n}\n";
  std::printf("%s: %zu boxes, %zu faces, sun at %g deg%s\n", dir.c_str(), boxes, city.faces.size(), elevation,
              ground_only ? ", the ground receives" : "");
  return scene.good() ? 0 : 1;
}

int run_prepare(const std::vector<std::size_t>& sizes, const std::vector<unsigned>& threads, int repeat, bool new_only) {
  bool all_same = true;
  std::printf("%9s %9s %7s | %13s %13s %7s | %13s %13s %7s | %13s %13s %7s | %s\n", "boxes", "faces", "threads",
              "validate ref", "validate new", "ratio", "orient ref", "orient new", "ratio", "solids ref", "solids new",
              "ratio", "same");
  for (std::size_t boxes : sizes) {
    const double extent = 500.0 * std::sqrt(static_cast<double>(boxes) / 1000.0);
    const shadow::Scene city = shadow::make_city(boxes, extent, 2026);
    // The reference once per size (it runs on one thread whatever the count).
    shadow::Scene reference = city;
    double validate_ref = 1e300;
    for (int r = 0; r < (new_only ? 0 : repeat); ++r) {
      reference = city;
      validate_ref = std::min(validate_ref, seconds_of([&] { shadow::detail::validate_scene_reference(reference); }));
    }
    // Faces prepared as the engine prepares them.
    if (new_only) shadow::validate_scene(reference);
    std::vector<shadow::core::FacePrep> prep(reference.faces.size());
    shadow::runtime::parallel_for(prep.size(), shadow::runtime::resolve_threads(0), [&](unsigned, std::size_t f) {
      const shadow::Face& face = reference.faces[f];
      if (face.degenerate || face.vertices.size() < 3)
        prep[f].degenerate = true;
      else
        prep[f] = shadow::exact::prepare_face(face.vertices);
    });
    // The orientation check alone (validate_scene's last step) on the validated city, serial
    // reference against the new one; orient outward off, so the scene stays as it is.
    std::vector<std::string> ref_warnings;
    double orient_ref = 1e300;
    for (int r = 0; r < (new_only ? 0 : repeat); ++r) {
      shadow::Scene copy = reference;
      orient_ref = std::min(orient_ref, seconds_of([&] {
                              ref_warnings = texts(shadow::detail::check_mesh_orientation(copy, {}, true));
                            }));
    }
    std::vector<int> ref_of;
    std::vector<shadow::core::ConvexSolid> ref_solids;
    double solids_ref = 1e300;
    for (int r = 0; r < (new_only ? 0 : repeat); ++r)
      solids_ref = std::min(solids_ref, seconds_of([&] {
                              ref_solids = shadow::exact::find_convex_solids_reference(reference, prep, ref_of);
                            }));
    for (unsigned t : threads) {
      shadow::LoadOptions options;
      options.threads = t;
      shadow::Scene scene = city;
      double validate_new = 1e300;
      for (int r = 0; r < repeat; ++r) {
        scene = city;
        validate_new = std::min(validate_new, seconds_of([&] { shadow::validate_scene(scene, options); }));
      }
      std::vector<std::string> orient_warnings;
      double orient_new = 1e300;
      for (int r = 0; r < repeat; ++r) {
        shadow::Scene copy = scene;
        orient_new = std::min(orient_new, seconds_of([&] {
                                orient_warnings = texts(shadow::detail::check_mesh_orientation(copy, options, false));
                              }));
      }
      std::vector<int> of;
      std::vector<shadow::core::ConvexSolid> solids;
      double solids_new = 1e300;
      for (int r = 0; r < repeat; ++r)
        solids_new = std::min(solids_new, seconds_of([&] { solids = shadow::exact::find_convex_solids(scene, prep, of, t); }));
      const bool same = same_faces(scene, reference) && same_solids(solids, of, ref_solids, ref_of) &&
                        orient_warnings == ref_warnings;
      all_same = all_same && (same || new_only);
      if (new_only)
        std::printf("%9zu %9zu %7u | %13s %11.3f s %7s | %13s %11.3f s %7s | %13s %11.3f s %7s | -\n", boxes,
                    city.faces.size(), t, "-", validate_new, "-", "-", orient_new, "-", "-", solids_new, "-");
      else
        std::printf("%9zu %9zu %7u | %11.3f s %11.3f s %6.1fx | %11.3f s %11.3f s %6.1fx | %11.3f s %11.3f s %6.1fx | %s\n",
                    boxes, city.faces.size(), t, validate_ref, validate_new, validate_ref / validate_new, orient_ref,
                    orient_new, orient_ref / orient_new, solids_ref, solids_new, solids_ref / solids_new,
                    same ? "yes" : "NO");
      std::fflush(stdout);
    }
  }
  return all_same ? 0 : 1;
}

}  // namespace bench
