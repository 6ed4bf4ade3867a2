// SPDX-License-Identifier: GPL-3.0-or-later
// The options of `shadow render`, declared in the `shadow` program itself: its --help and its
// usage errors need no rendering library. The rendering runs in the render module
// (render_command.cpp, loaded by render_module.cpp only when a picture is asked for).
#include "render_command.hpp"

#include "cli_checks.hpp"

#include <shadow/lighting.hpp>
#include <shadow/render/vector_drawing.hpp>

#include <string>
#include <vector>

void add_render_options(CLI::App& render, RenderArgs& args) {
  render.add_option("scene", args.scene, "Scene file (JSON; see docs/scene-format.md)")->required();
  render.add_option("-o,--output", args.image,
                    "File to write: .png (a picture), .svg or .pdf (the exact vector view, docs/vector-views.md); "
                    "other extensions are refused, and the folder must exist")
      ->required();
  render.add_option("--width", args.width, "Image width in pixels")->default_val(800)->check(shadow_cli::integer_in(1, 16384));
  render.add_option("--height", args.height, "Image height in pixels")->default_val(600)->check(shadow_cli::integer_in(1, 16384));
  render.add_option("--model", args.model,
                    "Lighting model: ambient, lambert, half-lambert, modified-half-lambert, phong, blinn-phong")
      ->default_val("blinn-phong")
      ->check(CLI::IsMember({"ambient", "lambert", "half-lambert", "modified-half-lambert", "phong", "blinn-phong"}));
  render.add_option("--shading", args.shading, "Shading method: flat, gouraud, phong (per pixel)")
      ->default_val("phong")
      ->check(CLI::IsMember({"flat", "gouraud", "phong"}));
  render.add_option("--attenuation", args.attenuation,
                    "Fall-off with distance: none, inverse-square (1/r^2 from point lights), "
                    "viewer-linear (1/(d+K), d from the viewer: seeds 000/001), light-linear (1/(d+K), d from "
                    "point lights)")
      ->default_val("none")
      ->check(CLI::IsMember({"none", "inverse-square", "viewer-linear", "light-linear"}));
  render.add_option("-K,--attenuation-k", args.attenuation_k, "K of the linear attenuation 1/(d+K)")
      ->default_val(1.0)
      ->check(shadow_cli::positive_up_to(1e150));
  render.add_option("--ambient", args.ambient, "Ambient light intensity i_a")
      ->default_val(1.0)
      ->check(shadow_cli::finite_in(0.0, 1e150));
  render.add_option("--back-intensity", args.back_intensity,
                    "modified-half-lambert: intensity I_B of the back (fill) light")
      ->default_val(0.5)
      ->check(shadow_cli::finite_in(0.0, 1e150));
  // Each coordinate a finite number (NaN and inf parse as doubles), small enough that the
  // camera's vector products cannot overflow.
  const CLI::Validator coordinate(
      [](std::string& text) -> std::string {
        char* end = nullptr;
        const double value = std::strtod(text.c_str(), &end);
        if (end == text.c_str() || *end != '\0' || !std::isfinite(value) || std::abs(value) > 1e150)
          return "expected a finite coordinate of magnitude at most 1e150, got " + text;
        return {};
      },
      "COORDINATE");
  render.add_option("--eye", args.eye, "Camera position x,y,z (default: frames the scene)")
      ->expected(3)
      ->delimiter(',')
      ->check(coordinate);
  render.add_option("--target,--look-at", args.target, "Point the camera looks at x,y,z (default: the scene's centre)")
      ->expected(3)
      ->delimiter(',')
      ->check(coordinate);
  render.add_option("--up", args.up, "Camera up direction x,y,z")
      ->expected(3)
      ->delimiter(',')
      ->default_str("0,0,1")
      ->check(coordinate);
  render.add_option("--fov", args.fov, "Vertical view angle in degrees (default: the scene's camera, or 30)")
      ->check(shadow_cli::finite_in(1.0, 170.0))
      ->each([&args](const std::string&) { args.fov_given = true; });
  render.add_option("--colours,--colors", args.colours,
                    "Meshes without a material: palette (the ground, buildings and other meshes each "
                    "their colour) or white (the lighting models' default material)")
      ->default_val("palette")
      ->check(CLI::IsMember({"palette", "white"}));
  render.add_option("--exposure", args.exposure,
                    "auto (scale down so that lit surfaces are not clipped: the 99th percentile of the "
                    "brightest channel at 0.85; --radiosity-mode colour: up or down) or a factor for the colours "
                    "(1: the models' values; --radiosity-mode colour: per W/m2)")
      ->default_val("auto")
      ->check([](const std::string& text) -> std::string {
        if (text == "auto") return {};
        char* end = nullptr;
        const double value = std::strtod(text.c_str(), &end);
        if (end == text.c_str() || *end != '\0' || !std::isfinite(value) || !(value > 0.0) || value > 1e6)
          return "expected auto or a factor in (0, 1e6], got " + text;
        return {};
      });
  render.add_option("--tone", args.tone,
                    "Values above 0.8: soft (run smoothly toward white) or clip (cut at 1)")
      ->default_val("soft")
      ->check(CLI::IsMember({"soft", "clip"}));
  render.add_option("--irradiation", args.irradiation,
                    "PNG: colour each face by its total irradiation (kWh/m2) from this `shadow irradiance` "
                    "OUTDIR or its report.json, with a legend of the scale, instead of lighting it "
                    "(SCENE must be the scene of that run)");
  render.add_option("--radiosity", args.radiosity,
                    "PNG: draw the elements of this `shadow radiosity` OUTDIR (or its radiosity.vtp or report.json) "
                    "coloured by their values, fronts only, instead of lighting the scene (SCENE must be the scene of "
                    "that run; docs/radiosity.md)");
  render.add_option("--radiosity-mode", args.radiosity_mode,
                    "--radiosity: radiosity or irradiance (W/m2 on a scale, with its legend), or colour (each "
                    "element's emittance + RGB reflectance x irradiance, through --exposure)")
      ->default_val("radiosity")
      ->check(CLI::IsMember({"radiosity", "irradiance", "colour", "color"}))
      ->each([&args](const std::string&) { args.radiosity_mode_given = true; });
  render.add_flag("--smooth", args.smooth,
                  "--radiosity: average the element values at the vertices they share on a face and interpolate "
                  "(Gouraud); without it each element is flat");
  render.add_flag("--legend", args.legend, "Draw a legend: each mesh group's colour lit and in shadow, and the lights");
  render.add_option("--compass", args.compass,
                    "Draw a compass (north, and the suns' directions on the ground): on, off, or auto (on when "
                    "the scene has a sun block)")
      ->default_val("auto")
      ->check(CLI::IsMember({"auto", "on", "off"}));
  render.add_option("--frame", args.frame,
                    "What the default camera frames: shadows (the meshes but the ground, and their shadows "
                    "on it) or scene (every vertex, the whole ground included; the default with --irradiation and --radiosity)")
      ->default_val("shadows")
      ->check(CLI::IsMember({"shadows", "scene"}))
      ->each([&args](const std::string&) { args.frame_given = true; });
  render.add_option("-t,--threads", args.threads, "Worker threads for the shadows (0: all cores; at most 1024)")
      ->default_val(0)
      ->check(shadow_cli::integer_in(0, 1024));
  render.add_flag("-q,--quiet", args.quiet, "Print nothing but errors");
  render.add_option("--light", args.light, "SVG/PDF: the light whose shadows split the pieces (default: the first)")
      ->check(shadow_cli::integer_in(0, 1 << 30));
  render.add_flag("--edges", args.edges, "SVG/PDF: outline every piece");
  render.add_option("--max-faces", args.max_faces,
                    "SVG/PDF: refuse a scene of more faces (the exact view's cost grows faster than the face "
                    "count; a PNG has no such bound)")
      ->default_val(shadow::render::kDefaultMaxVectorFaces)
      ->check(shadow_cli::integer_in(1, 100'000'000))
      ->each([&args](const std::string&) { args.max_faces_given = true; });
  // The loading options of `shadow compute` and `shadow series`: what they load, render draws.
  render.add_option("--planarity-tolerance", args.planarity_tolerance,
                    "Largest vertex distance from a face's plane, relative to the face's size")
      ->default_val(1e-6)
      ->check(shadow_cli::positive_up_to(1.0));
  render.add_flag("--orient-outward", args.orient_outward,
                  "Turn the closed parts of every mesh outward (as for `shadow compute`)");
  render.add_option("--lod", args.lod, "CityJSON level of detail to read (default: the highest of each city object)");
  render.add_flag("--skip-invalid", args.skip_invalid, shadow_cli::skip_invalid_help());
}
