// SPDX-License-Identifier: GPL-3.0-or-later
// The `shadow render` subcommand (built when VTK's OpenGL rendering is available).
#pragma once

#include <CLI/CLI.hpp>

#include <shadow/render/camera.hpp>
#include <shadow/scene_io.hpp>
#include <shadow/view.hpp>

#include <string>
#include <vector>

struct RenderArgs {
  std::string scene;
  std::string image;
  int width = 800;
  int height = 600;
  std::string model = "blinn-phong";
  std::string shading = "phong";
  std::string attenuation = "none";
  double attenuation_k = 1.0;
  double ambient = 1.0;
  double back_intensity = 0.5;
  std::vector<double> eye;
  std::vector<double> target;
  std::vector<double> up;
  double fov = 30.0;
  bool fov_given = false;
  std::string frame = "shadows";
  std::string colours = "palette";
  std::string exposure = "auto";
  std::string tone = "soft";
  bool legend = false;
  /// --irradiation: a `shadow irradiance` OUTDIR (or its report.json) whose per-face totals
  /// colour the picture instead of the lighting (docs/render.md); empty: a shaded picture.
  std::string irradiation;
  /// --radiosity: a `shadow radiosity` OUTDIR (or its radiosity.vtp or report.json) whose
  /// elements are drawn (docs/radiosity.md, "Pictures"); empty: not a radiosity picture.
  std::string radiosity;
  std::string radiosity_mode = "radiosity";  ///< radiosity, irradiance or colour
  bool radiosity_mode_given = false;
  bool smooth = false;  ///< --smooth: element values averaged at shared vertices (Gouraud)
  bool frame_given = false;  ///< --frame was given (--irradiation, --radiosity frame the whole scene otherwise)
  std::string compass = "auto";
  unsigned threads = 0;
  bool quiet = false;
  int light = -1;      ///< SVG/PDF: the light that splits lit from shadowed (-1: the first, if any)
  bool edges = false;  ///< SVG/PDF: outline every piece
  std::size_t max_faces = 20000;  ///< SVG/PDF: refuse a view of more faces (its cost; docs/vector-views.md)
  bool max_faces_given = false;
  // Loading, as `shadow compute` and `shadow series` load (the same model gives the same faces).
  double planarity_tolerance = 1e-6;
  bool orient_outward = false;
  bool skip_invalid = false;  ///< --skip-invalid: leave out faces that fail validation
  std::string lod;  ///< CityJSON level of detail; empty: the highest per object
};

/// The load options of `shadow render` (PNG and vector views alike).
shadow::LoadOptions render_load_options(const RenderArgs& args);

/// Declares the options of `shadow render` on its subcommand.
void add_render_options(CLI::App& render, RenderArgs& args);

/// Runs `shadow render`; argc/argv are the whole command line, to start again under xvfb-run
/// when there is no display. @throws shadow::InputError, shadow::render::RenderError
int run_render(const RenderArgs& args, int argc, char** argv);

namespace shadow::render {
/// The camera of `shadow render` for a vector view: resolve_camera (shadow/render/camera.hpp), the
/// PNG's own choice, at the image's size. @throws InputError naming the options or the scene
shadow::ViewCamera vector_camera(const shadow::Scene& scene, const RenderArgs& args);

/// Runs `shadow render` for an .svg or .pdf output (render_vector_command.cpp).
/// @throws InputError, RenderError
int run_vector_render(const RenderArgs& args);
}  // namespace shadow::render
