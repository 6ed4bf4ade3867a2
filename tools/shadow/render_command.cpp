// SPDX-License-Identifier: GPL-3.0-or-later
// `shadow render SCENE.json -o image.png`: exact shadows, the seed lighting models, a picture.
#include "render_command.hpp"

#include "cli_checks.hpp"

#include <shadow/render/radiosity_picture.hpp>
#include <shadow/render/render_image.hpp>
#include <shadow/render/value_picture.hpp>
#include <shadow/render/vector_drawing.hpp>

#include <shadow/irradiance_output.hpp>
#include <shadow/radiosity_output.hpp>
#include <shadow/shadow.hpp>

#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cmath>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

/// Set in the environment of the copy of `shadow` started under xvfb-run, so that a display
/// that still does not work ends in an error instead of another restart.
constexpr const char* kUnderXvfb = "LIBSHADOW_RENDER_UNDER_XVFB";

bool on_path(const std::string& program) {
  const char* path = std::getenv("PATH");
  if (path == nullptr) return false;
  std::string dirs = path;
  std::size_t start = 0;
  while (start <= dirs.size()) {
    const std::size_t end = std::min(dirs.find(':', start), dirs.size());
    const fs::path candidate = fs::path(dirs.substr(start, end - start)) / program;
    if (access(candidate.c_str(), X_OK) == 0) return true;
    start = end + 1;
  }
  return false;
}

glm::dvec3 to_vec3(const std::vector<double>& v) { return {v[0], v[1], v[2]}; }

/// `-o`'s extension must be one `shadow render` writes: anything else used to get PNG bytes
/// under its name. A usage error, found before anything is loaded.
void check_output_extension(const std::string& image) {
  std::string ext = fs::path(image).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".png" || ext == ".svg" || ext == ".pdf") return;
  throw shadow::InputError({"", "--output"},
                           (ext.empty() ? "\"" + image + "\" has no extension"
                                        : "unknown image type \"" + fs::path(image).extension().string() + "\"") +
                               ": expected .png (a picture), .svg or .pdf (the exact vector view)");
}

/// The folder `-o` names must exist and take a new file before any work is done: a missing or
/// read-only folder used to show only after the shadows and the picture were computed.
void check_output_directory(const std::string& image) {
  const fs::path path(image);
  fs::path dir = path.parent_path();
  if (dir.empty()) dir = ".";
  std::error_code ec;
  const fs::file_status status = fs::status(dir, ec);
  if (!fs::exists(status))
    throw shadow::OutputError(dir.string() + ": the output directory does not exist (create it first)");
  if (!fs::is_directory(status)) throw shadow::OutputError(dir.string() + ": is not a directory");
  if (access(dir.c_str(), W_OK | X_OK) != 0)
    throw shadow::OutputError(dir.string() + ": cannot write into the output directory: " + std::strerror(errno));
  if (fs::is_directory(fs::status(path, ec)))
    throw shadow::OutputError(image + ": is a directory; cannot write the image there");
}

/// `--irradiation`: the faces coloured by the result's totals (no shadows to compute: they are
/// in the values), the legend always drawn.
int render_irradiation(const RenderArgs& args, const shadow::Scene& scene, const shadow::render::RenderOptions& options) {
  namespace sr = shadow::render;
  const shadow::IrradiationReport report = shadow::read_irradiation_report(args.irradiation);
  const std::vector<double> values = shadow::face_irradiation(scene, report);
  sr::RenderOptions adjusted = options;
  adjusted.legend = true;
  const sr::Image image = sr::render_face_values(scene, values, adjusted, "total irradiation, kWh/m\u00b2");
  sr::write_png(image, args.image);
  if (!args.quiet) {
    const sr::ValueScale scale = sr::value_scale(values);
    std::printf("shadow %s: %zu faces coloured by total irradiation from %s (%zu faces with a value; scale 0 to %g "
                "kWh/m2), %dx%d: %s\n",
                shadow::version(), scene.faces.size(), report.file.string().c_str(), report.faces.size(), scale.top,
                args.width, args.height, args.image.c_str());
  }
  return 0;
}

/// `--radiosity`: the elements of a `shadow radiosity` result, by value with the scale's legend
/// or in colour, flat or smooth; no shadows to compute (they are in the values).
int render_radiosity(const RenderArgs& args, const shadow::Scene& scene, const shadow::render::RenderOptions& options) {
  namespace sr = shadow::render;
  const shadow::RadiosityFiles files = shadow::read_radiosity_files(args.radiosity);
  shadow::check_radiosity_files(scene, files);
  sr::RadiosityPictureOptions picture;
  picture.mode = sr::parse_radiosity_mode(args.radiosity_mode);
  picture.smooth = args.smooth;
  const sr::Image image = sr::render_radiosity(scene, files, options, picture);
  sr::write_png(image, args.image);
  if (!args.quiet) {
    std::printf("shadow %s: %zu elements of %s coloured by %s (%s)", shadow::version(), files.elements.size(),
                files.vtp.string().c_str(), args.radiosity_mode.c_str(), args.smooth ? "smooth" : "flat");
    if (picture.mode == sr::RadiosityMode::Colour) std::printf(", exposure %.3g per W/m2", image.exposure);
    std::printf(", %dx%d: %s\n", args.width, args.height, args.image.c_str());
  }
  return 0;
}

}  // namespace

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

shadow::LoadOptions render_load_options(const RenderArgs& args) {
  return shadow_cli::load_options(args.planarity_tolerance, args.orient_outward, args.lod, args.threads,
                                  args.skip_invalid);
}

int run_render(const RenderArgs& args, int argc, char** argv) {
  namespace sr = shadow::render;
  check_output_extension(args.image);
  check_output_directory(args.image);
  if (!args.irradiation.empty() && sr::is_vector_output(args.image))
    throw shadow::InputError({"", "--irradiation"}, "draws a PNG picture, not the vector view " + args.image);
  if (!args.radiosity.empty() && sr::is_vector_output(args.image))
    throw shadow::InputError({"", "--radiosity"}, "draws a PNG picture, not the vector view " + args.image);
  if (!args.radiosity.empty() && !args.irradiation.empty())
    throw shadow::InputError({"", "--radiosity"}, "draws one result: give --radiosity or --irradiation, not both");
  if (args.radiosity.empty() && (args.smooth || args.radiosity_mode_given))
    throw shadow::InputError({"", args.smooth ? "--smooth" : "--radiosity-mode"},
                             "applies to a radiosity picture only (--radiosity OUTDIR)");
  // The exact vector view needs no display: dispatched before looking for one.
  if (sr::is_vector_output(args.image)) return sr::run_vector_render(args);
  if (args.light >= 0 || args.edges || args.max_faces_given)
    throw shadow::InputError({"", args.light >= 0 ? "--light" : args.edges ? "--edges" : "--max-faces"},
                             "applies to the vector view only (-o VIEW.svg or VIEW.pdf), not to " + args.image);
  // Debian's VTK draws through X even off screen; without a display, start again under Xvfb.
  if (!sr::display_available()) {
    if (std::getenv(kUnderXvfb) == nullptr && on_path("xvfb-run")) {
      setenv(kUnderXvfb, "1", 1);
      // This very binary, by its real path (/proc/self/exe would name xvfb-run's shell there).
      std::error_code error;
      const fs::path self = fs::read_symlink("/proc/self/exe", error);
      // -noreset: a server that resets when its last client leaves refuses the next connection
      // for a while, and VTK aborts when it cannot connect.
      std::vector<std::string> words = {"xvfb-run", "-a", "-s", "-screen 0 2048x2048x24 -noreset",
                                        error ? std::string(argv[0]) : self.string()};
      for (int i = 1; i < argc; ++i) words.emplace_back(argv[i]);
      std::vector<char*> exec_args;
      for (std::string& w : words) exec_args.push_back(w.data());
      exec_args.push_back(nullptr);
      execvp("xvfb-run", exec_args.data());
      throw sr::RenderError(std::string("cannot start xvfb-run: ") + std::strerror(errno));
    }
    throw sr::RenderError(
        "no X display (DISPLAY is not set) and no xvfb-run on the PATH to make one: install the packages "
        "xvfb and xauth (shadow render then starts itself under xvfb-run), or point DISPLAY at an X server");
  }

  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  shadow::LoadOptions load = render_load_options(args);
  // The scene of an irradiance run may leave its lights out: the suns came from the weather; a
  // radiosity run's light may all come from emitting faces.
  const bool values = !args.irradiation.empty() || !args.radiosity.empty();
  if (values) load.require_lights = false;
  shadow::Scene scene = shadow::load_scene(args.scene, load);
  if (!args.quiet)
    for (const shadow::Warning& warning : scene.warnings)
      std::cerr << "shadow: warning: " << warning.to_string() << "\n";
  // A picture shows every face lit as it is, whatever the scene's `receivers` say.
  for (shadow::Mesh& mesh : scene.meshes) mesh.receiver = true;
  // A picture has hard shadows: an extended light lights it from its centre (docs/render.md).
  for (shadow::Light& light : scene.lights)
    if (light.is_extended()) light = shadow::centre_light(light);

  sr::RenderOptions options;
  options.width = args.width;
  options.height = args.height;
  shadow::parse_lighting_model(args.model, options.shade.lighting.model);
  shadow::parse_attenuation(args.attenuation, options.shade.lighting.attenuation);
  sr::parse_shading(args.shading, options.shade.shading);
  options.shade.lighting.attenuation_k = args.attenuation_k;
  options.shade.lighting.ambient_intensity = args.ambient;
  options.shade.lighting.back_intensity = args.back_intensity;
  if (args.colours == "palette") options.shade.palette = sr::Palette{};
  options.shade.exposure.automatic = args.exposure == "auto";
  if (args.exposure != "auto") options.shade.exposure.scale = std::strtod(args.exposure.c_str(), nullptr);
  options.shade.exposure.soft_shoulder = args.tone == "soft";
  // --irradiation and --radiosity by value: their scale always
  options.legend = args.legend || !args.irradiation.empty() ||
                   (!args.radiosity.empty() && args.radiosity_mode != "colour" && args.radiosity_mode != "color");
  options.compass = args.compass == "on" || (args.compass == "auto" && scene.sun.has_value());
  sr::CameraRequest request;
  if (!args.eye.empty()) request.eye = to_vec3(args.eye);
  if (!args.target.empty()) request.target = to_vec3(args.target);
  if (!args.up.empty()) request.up = to_vec3(args.up);
  if (args.fov_given) request.fov_degrees = args.fov;
  // An irradiation or radiosity picture is about every face, the ground's too: the whole scene
  // unless told.
  const bool whole = args.frame == "scene" || (values && !args.frame_given);
  request.framing = whole ? sr::Framing::Scene : sr::Framing::Shadows;
  request.scene_file = args.scene;
  // Room for the corner marks: the framing keeps clear of them.
  if (options.legend || options.compass) request.margin = 0.12;
  // the default framing, then the scene's "camera", then the options
  options.shade.camera = sr::resolve_camera(scene, request, static_cast<double>(args.width) / args.height);

  if (!args.irradiation.empty()) return render_irradiation(args, scene, options);
  if (!args.radiosity.empty()) return render_radiosity(args, scene, options);

  shadow::ShadowOptions shadow_options;
  shadow_options.threads = args.threads;
  shadow_options.planes = false;
  shadow::ShadowResult result;
  try {
    result = shadow::compute_shadows(scene, shadow_options);
  } catch (const shadow::InputError& e) {
    throw shadow::InputError({args.scene, e.where().place}, e.problem());
  }
  const auto computed = Clock::now();
  const sr::Image image = sr::render_scene(scene, result, options);
  sr::write_png(image, args.image);
  if (!args.quiet) {
    auto seconds = [](Clock::duration d) { return std::chrono::duration<double>(d).count(); };
    std::printf("shadow %s: %zu faces, %zu lights, %zu fragments; %s model, %s shading, %dx%d\n",
                shadow::version(), scene.faces.size(), scene.lights.size(), result.fragments.size(),
                args.model.c_str(), args.shading.c_str(), args.width, args.height);
    std::printf("  exposure %.3g; shadows in %.3f s, picture in %.3f s: %s\n", image.exposure,
                seconds(computed - start), seconds(Clock::now() - computed), args.image.c_str());
  }
  return 0;
}
