// SPDX-License-Identifier: GPL-3.0-or-later
// `shadow render SCENE.json -o image.png`: exact shadows, the seed lighting models, a picture.
// Built into the render module (render_module.hpp), which `shadow` loads for this subcommand only.
#include "render_command.hpp"
#include "render_module.hpp"

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

// The render module's exports (render_module.hpp).
extern "C" {
__attribute__((visibility("default"))) std::size_t shadow_render_module_args_size() { return sizeof(RenderArgs); }

__attribute__((visibility("default"))) int shadow_render_module_run(const RenderArgs& args, int argc, char** argv) {
  try {
    return run_render(args, argc, argv);
  } catch (const shadow::render::RenderError& e) {
    std::cerr << "shadow: error: " << e.what() << "\n";
    return 3;  // an output failure, as shadow_main.cpp's exit codes say
  }
}
}
