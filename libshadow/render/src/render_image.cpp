// SPDX-License-Identifier: GPL-3.0-or-later
#include <shadow/render/render_image.hpp>

#include <shadow/render/camera.hpp>

#include "writers/vtk_errors.hpp"  // io_internal: VTK errors as one line

#include <shadow/output.hpp>

#include <vtkActor.h>
#include <vtkActor2D.h>
#include <vtkPolyDataMapper2D.h>
#include <vtkProperty2D.h>
#ifdef LIBSHADOW_RENDER_TEXT
#include <vtkTextActor.h>
#include <vtkTextProperty.h>
#endif
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCommand.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGWriter.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkUnsignedCharArray.h>
#include <vtkWindowToImageFilter.h>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

namespace shadow::render {
namespace {

/// Linear RGB in [0, 1] to an 8-bit sRGB value: the models compute linear light, screens and
/// PNG viewers expect sRGB (without it mid-tones look far too dark).
std::uint8_t to_byte(double linear) {
  const double c = std::clamp(linear, 0.0, 1.0);
  const double encoded = c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055;
  return static_cast<std::uint8_t>(std::lround(255.0 * encoded));
}

vtkSmartPointer<vtkUnsignedCharArray> colour_array(const std::vector<glm::dvec3>& colours) {
  auto array = vtkSmartPointer<vtkUnsignedCharArray>::New();
  array->SetName("colour");
  array->SetNumberOfComponents(3);
  array->SetNumberOfTuples(static_cast<vtkIdType>(colours.size()));
  for (std::size_t i = 0; i < colours.size(); ++i) {
    const auto id = static_cast<vtkIdType>(i);
    array->SetTypedComponent(id, 0, to_byte(colours[i].r));
    array->SetTypedComponent(id, 1, to_byte(colours[i].g));
    array->SetTypedComponent(id, 2, to_byte(colours[i].b));
  }
  return array;
}

/// 2D shapes in pixels (origin bottom left), each filled polygon or line with its own colour.
class Shapes {
 public:
  void polygon(const std::vector<glm::dvec2>& corners, const glm::dvec3& colour) {
    std::vector<vtkIdType> ids;
    for (const glm::dvec2& c : corners) ids.push_back(points_->InsertNextPoint(c.x, c.y, 0.0));
    polys_->InsertNextCell(static_cast<vtkIdType>(ids.size()), ids.data());
    poly_colours_.push_back(colour);
  }
  void line(const std::vector<glm::dvec2>& corners, const glm::dvec3& colour) {
    std::vector<vtkIdType> ids;
    for (const glm::dvec2& c : corners) ids.push_back(points_->InsertNextPoint(c.x, c.y, 0.0));
    lines_->InsertNextCell(static_cast<vtkIdType>(ids.size()), ids.data());
    line_colours_.push_back(colour);
  }
  void add_to(vtkRenderer* renderer) {
    vtkNew<vtkPolyData> data;
    data->SetPoints(points_);
    data->SetPolys(polys_);
    data->SetLines(lines_);
    // VTK orders cell data verts, lines, polys.
    std::vector<glm::dvec3> colours = line_colours_;
    colours.insert(colours.end(), poly_colours_.begin(), poly_colours_.end());
    auto array = vtkSmartPointer<vtkUnsignedCharArray>::New();
    array->SetNumberOfComponents(3);
    for (const glm::dvec3& c : colours) {
      const unsigned char rgb[3] = {static_cast<unsigned char>(std::lround(255 * std::clamp(c.r, 0.0, 1.0))),
                                    static_cast<unsigned char>(std::lround(255 * std::clamp(c.g, 0.0, 1.0))),
                                    static_cast<unsigned char>(std::lround(255 * std::clamp(c.b, 0.0, 1.0)))};
      array->InsertNextTypedTuple(rgb);
    }
    data->GetCellData()->SetScalars(array);
    vtkNew<vtkPolyDataMapper2D> mapper;
    mapper->SetInputData(data);
    mapper->SetColorModeToDirectScalars();
    mapper->SetScalarModeToUseCellData();
    vtkNew<vtkActor2D> actor;
    actor->SetMapper(mapper);
    actor->GetProperty()->SetLineWidth(2.0);
    renderer->AddActor2D(actor);
  }

 private:
  vtkNew<vtkPoints> points_;
  vtkNew<vtkCellArray> polys_;
  vtkNew<vtkCellArray> lines_;
  std::vector<glm::dvec3> poly_colours_, line_colours_;
};

std::vector<glm::dvec2> disk(const glm::dvec2& centre, double radius, int sides) {
  std::vector<glm::dvec2> corners;
  for (int i = 0; i < sides; ++i) {
    const double a = 2.0 * M_PI * i / sides;
    corners.emplace_back(centre.x + radius * std::cos(a), centre.y + radius * std::sin(a));
  }
  return corners;
}

/// Where world point `p` appears, in pixels from the bottom left (perspective of `c`).
glm::dvec2 to_pixels(const Camera& c, const glm::dvec3& p, int width, int height) {
  const glm::dvec3 view = glm::normalize(c.target - c.eye);
  const glm::dvec3 right = glm::normalize(glm::cross(view, c.up));
  const glm::dvec3 up = glm::cross(right, view);
  const glm::dvec3 o = p - c.eye;
  const double depth = std::max(glm::dot(o, view), 1e-300);
  const double tan_v = std::tan(0.5 * c.fov_degrees * M_PI / 180.0);
  const double x = glm::dot(o, right) / (depth * tan_v * width / height);
  const double y = glm::dot(o, up) / (depth * tan_v);
  return {0.5 * (x + 1.0) * width, 0.5 * (y + 1.0) * height};
}

/// The legend and the compass, as 2D actors over the picture.
void add_decorations(vtkRenderer* renderer, const Decorations& d, const RenderOptions& options) {
  Shapes shapes;
  std::vector<vtkSmartPointer<vtkProp>> texts;  // drawn after the shapes, over them
  const glm::dvec3 ink(0.15, 0.17, 0.2), paper(1.0, 1.0, 1.0);
  const double unit = std::clamp(options.height / 600.0, 0.5, 3.0);  // sizes scale with the picture
  if (!d.legend.empty()) {
    const double row = 18 * unit, sw = 14 * unit, left = 10 * unit;
    const double lines = 1.0 + static_cast<double>(d.legend.size() + d.notes.size());  // a header, rows, notes
    const double top = options.height - 10 * unit;
    // Wide enough for the longest line (about 0.6 em a character at 12 points).
    std::size_t longest = std::max<std::size_t>(14, d.header.size());
    for (const LegendEntry& e : d.legend) longest = std::max(longest, e.label.size() + 5);
    for (const std::string& n : d.notes) longest = std::max(longest, n.size());
    const double width = std::min(std::max(180.0, 7.0 * static_cast<double>(longest) + 10.0), 0.9 * options.width / unit) * unit;
    auto line_y = [&](std::size_t line) { return top - (static_cast<double>(line) + 1.0) * row; };  // its bottom
    shapes.polygon({{left - 4 * unit, top + 4 * unit}, {left - 4 * unit, top - lines * row - 4 * unit},
                    {left + width, top - lines * row - 4 * unit}, {left + width, top + 4 * unit}},
                   paper);
    for (std::size_t i = 0; i < d.legend.size(); ++i) {
      const double y = line_y(i + 1);
      shapes.polygon({{left, y}, {left + sw, y}, {left + sw, y + sw}, {left, y + sw}}, d.legend[i].lit);
      shapes.polygon({{left + sw + 3 * unit, y}, {left + 2 * sw + 3 * unit, y}, {left + 2 * sw + 3 * unit, y + sw},
                      {left + sw + 3 * unit, y + sw}},
                     d.legend[i].shadow);
    }
#ifdef LIBSHADOW_RENDER_TEXT
    auto text = [&](const std::string& words, double x, double y, bool bold) {
      vtkNew<vtkTextActor> actor;
      texts.push_back(actor);
      actor->SetInput(words.c_str());
      actor->SetDisplayPosition(static_cast<int>(x), static_cast<int>(y));
      actor->GetTextProperty()->SetFontSize(static_cast<int>(12 * unit));
      actor->GetTextProperty()->SetColor(ink.r, ink.g, ink.b);
      actor->GetTextProperty()->SetBold(bold);
      actor->GetTextProperty()->SetFontFamilyToArial();
    };
    text(d.header, left, line_y(0) + 2 * unit, true);
    for (std::size_t i = 0; i < d.legend.size(); ++i) text(d.legend[i].label, left + 2 * sw + 10 * unit, line_y(i + 1) + 2 * unit, false);
    for (std::size_t i = 0; i < d.notes.size(); ++i) text(d.notes[i], left, line_y(d.legend.size() + 1 + i) + 2 * unit, false);
#endif
  }
  if (d.compass) {
    const double radius = 32 * unit;
    const glm::dvec2 centre(options.width - radius - 14 * unit, radius + 14 * unit);
    shapes.polygon(disk(centre, radius, 48), glm::dvec3(1.0));
    std::vector<glm::dvec2> ring = disk(centre, radius, 48);
    ring.push_back(ring.front());
    shapes.line(ring, ink);
    // A ground direction as it appears on screen, from the anchor.
    const Camera& camera = options.shade.camera;
    const double step = 1e-3 * std::max(1.0, glm::length(camera.target - camera.eye));
    auto screen_direction = [&](const glm::dvec3& w) {
      const glm::dvec2 a = to_pixels(camera, d.anchor, options.width, options.height);
      const glm::dvec2 b = to_pixels(camera, d.anchor + step * glm::normalize(w), options.width, options.height);
      const glm::dvec2 v = b - a;
      return glm::length(v) > 0 ? v / glm::length(v) : glm::dvec2(0.0, 1.0);
    };
    for (const glm::dvec3& sun : d.suns) {
      const glm::dvec2 s = screen_direction(sun);
      shapes.polygon(disk(centre + 0.78 * radius * s, 4.0 * unit, 12), glm::dvec3(0.98, 0.66, 0.1));
    }
    const glm::dvec2 n = screen_direction(d.north);
    const glm::dvec2 side(-n.y, n.x);
    shapes.polygon({centre + 0.7 * radius * n, centre - 0.35 * radius * n + 0.28 * radius * side, centre,
                    centre - 0.35 * radius * n - 0.28 * radius * side},
                   ink);
    // The letter N beyond the tip, upright: three strokes.
    const glm::dvec2 at = centre + 0.72 * radius * n + glm::dvec2(0.0, 0.0);
    const double h = 9 * unit, w = 6 * unit;
    const glm::dvec2 base = at + glm::dvec2(-w / 2, -h / 2) + (n * (h * 0.9));
    shapes.line({base, base + glm::dvec2(0, h), base + glm::dvec2(w, 0), base + glm::dvec2(w, h)}, ink);
  }
  shapes.add_to(renderer);
  for (const auto& t : texts) renderer->AddActor2D(t);
}

}  // namespace

Decorations make_decorations(const Scene& scene, const RenderOptions& options, double exposure) {
  Decorations d;
  if (options.legend) {
    // One row per colour: a type (windows, roofs, terrain, ...) or the meshes that share it.
    const DisplayGroups groups = display_groups(scene, options.shade.palette);
    std::vector<char> used(groups.groups.size(), 0);
    for (std::size_t g : groups.face_group) used[g] = 1;
    auto srgb = [](const glm::dvec3& linear) {
      glm::dvec3 out;
      for (int i = 0; i < 3; ++i)
        out[i] = linear[i] <= 0.0031308 ? 12.92 * linear[i] : 1.055 * std::pow(linear[i], 1.0 / 2.4) - 0.055;
      return out;
    };
    for (std::size_t g = 0; g < groups.groups.size(); ++g) {
      if (!used[g]) continue;
      if (d.legend.size() == 8) break;
      const Material* material = &groups.groups[g].material;
      LegendEntry entry;
      entry.label = groups.groups[g].label;
      // An upward surface, lit by every light at its strongest (diffuse, no highlight), and in
      // every light's shadow.
      double diffuse = 0.0;
      for (const Light& light : scene.lights)
        diffuse += light.intensity * std::max(0.0, light.type == LightType::Directional
                                                       ? glm::normalize(light.to_light).z
                                                       : 1.0);
      const glm::dvec3 ambient = material->k_a * options.shade.lighting.ambient_intensity * material->color;
      entry.lit = srgb(expose(ambient + material->k_d * diffuse * material->color, options.shade.exposure, exposure));
      entry.shadow = srgb(expose(ambient, options.shade.exposure, exposure));
      d.legend.push_back(entry);
    }
    std::size_t directional = 0, points = 0, extended = 0;
    for (const Light& light : scene.lights) {
      if (light.is_extended()) ++extended;
      else if (light.type == LightType::Directional) ++directional;
      else ++points;
    }
    if (scene.lights.size() <= 3) {
      for (const Light& light : scene.lights) {
        char line[160];
        if (light.type == LightType::Directional) {
          const glm::dvec3 l = glm::normalize(light.to_light);
          std::snprintf(line, sizeof line, "light %s: directional, %.0f deg up", light.name.c_str(),
                        std::asin(std::clamp(l.z, -1.0, 1.0)) * 180.0 / M_PI);
        } else if (light.type == LightType::Point) {
          std::snprintf(line, sizeof line, "light %s: point at (%.3g, %.3g, %.3g)", light.name.c_str(),
                        light.position.x, light.position.y, light.position.z);
        } else {
          std::snprintf(line, sizeof line, "light %s: %s", light.name.c_str(),
                        light.type == LightType::Area ? "area" : "disk");
        }
        d.notes.emplace_back(line);
      }
    } else {
      d.notes.push_back(std::to_string(scene.lights.size()) + " lights: " + std::to_string(directional) +
                        " directional, " + std::to_string(points) + " point, " + std::to_string(extended) +
                        " extended");
    }
  }
  if (options.compass) {
    d.compass = true;
    double north_axis = scene.sun ? scene.sun->north_axis : 0.0;
    const double a = north_axis * M_PI / 180.0;
    d.north = glm::dvec3(-std::sin(a), std::cos(a), 0.0);  // true north in the model (docs/sun.md)
    glm::dvec3 lo(1e300), hi(-1e300);
    for (const Face& face : scene.faces)
      for (const glm::dvec3& v : face.vertices) {
        lo = glm::min(lo, v);
        hi = glm::max(hi, v);
      }
    if (lo.x <= hi.x) d.anchor = glm::dvec3(0.5 * (lo.x + hi.x), 0.5 * (lo.y + hi.y), lo.z);
    for (const Light& light : scene.lights)
      if (light.type == LightType::Directional && light.to_light.z > 0 &&
          std::hypot(light.to_light.x, light.to_light.y) > 1e-9 * glm::length(light.to_light))
        d.suns.emplace_back(light.to_light.x, light.to_light.y, 0.0);
  }
  return d;
}

bool display_available() {
  const char* display = std::getenv("DISPLAY");
  return display != nullptr && display[0] != '\0';
}

Image render_mesh(const ColouredMesh& mesh, const RenderOptions& options, const Decorations& decorations) {
  if (options.width <= 0 || options.height <= 0)
    throw RenderError("image size must be positive, got " + std::to_string(options.width) + "x" +
                      std::to_string(options.height));
  // Debian's VTK opens an X connection even off screen and aborts the process without one.
  if (!display_available())
    throw RenderError("no X display (DISPLAY is not set): VTK's OpenGL needs one; run under "
                      "`xvfb-run -a` on a headless machine");

  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(static_cast<vtkIdType>(mesh.points.size()));
  for (std::size_t i = 0; i < mesh.points.size(); ++i)
    points->SetPoint(static_cast<vtkIdType>(i), mesh.points[i].x, mesh.points[i].y, mesh.points[i].z);
  vtkNew<vtkCellArray> triangles;
  for (std::size_t t = 0; t + 2 < mesh.triangles.size(); t += 3) {
    const vtkIdType ids[3] = {static_cast<vtkIdType>(mesh.triangles[t]),
                              static_cast<vtkIdType>(mesh.triangles[t + 1]),
                              static_cast<vtkIdType>(mesh.triangles[t + 2])};
    triangles->InsertNextCell(3, ids);
  }
  vtkNew<vtkPolyData> poly;
  poly->SetPoints(points);
  poly->SetPolys(triangles);

  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputData(poly);
  mapper->ScalarVisibilityOn();
  mapper->SetColorModeToDirectScalars();  // our colours as they are, no lookup table
  if (!mesh.triangle_colours.empty()) {
    poly->GetCellData()->SetScalars(colour_array(mesh.triangle_colours));
    mapper->SetScalarModeToUseCellData();
  } else {
    poly->GetPointData()->SetScalars(colour_array(mesh.point_colours));
    mapper->SetScalarModeToUsePointData();
    mapper->InterpolateScalarsBeforeMappingOff();
  }

  vtkNew<vtkActor> actor;
  actor->SetMapper(mapper);
  // The lighting model has been evaluated already: VTK must show the colours unchanged.
  actor->GetProperty()->LightingOff();
  actor->GetProperty()->SetAmbient(1.0);
  actor->GetProperty()->SetDiffuse(0.0);
  actor->GetProperty()->SetSpecular(0.0);
  if (options.cull_back_faces) actor->GetProperty()->BackfaceCullingOn();

  vtkNew<vtkRenderer> renderer;
  renderer->AddActor(actor);
  renderer->SetBackground(options.background.r, options.background.g, options.background.b);
  renderer->AutomaticLightCreationOff();
  vtkCamera* camera = renderer->GetActiveCamera();
  const Camera& c = options.shade.camera;
  camera->SetPosition(c.eye.x, c.eye.y, c.eye.z);
  camera->SetFocalPoint(c.target.x, c.target.y, c.target.z);
  camera->SetViewUp(c.up.x, c.up.y, c.up.z);
  camera->SetViewAngle(c.fov_degrees);
  camera->OrthogonalizeViewUp();
  renderer->ResetCameraClippingRange();
  if (!decorations.legend.empty() || decorations.compass) add_decorations(renderer, decorations, options);

  vtkNew<vtkRenderWindow> window;
  vtkNew<detail::VtkErrorCapture> errors;  // a failure becomes one RenderError line
  window->AddObserver(vtkCommand::ErrorEvent, errors);
  window->SetOffScreenRendering(1);
  window->SetMultiSamples(0);  // no multisampling: the same pixels on every run
  window->SetSize(options.width, options.height);
  window->AddRenderer(renderer);
  window->Render();
  if (!errors->message().empty()) throw RenderError("VTK could not render: " + errors->message());

  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window);
  grab->SetInputBufferTypeToRGB();
  grab->ReadFrontBufferOff();
  grab->Update();
  vtkImageData* frame = grab->GetOutput();
  int dims[3];
  frame->GetDimensions(dims);
  if (dims[0] != options.width || dims[1] != options.height)
    throw RenderError("VTK returned a " + std::to_string(dims[0]) + "x" + std::to_string(dims[1]) +
                      " image instead of " + std::to_string(options.width) + "x" + std::to_string(options.height));

  Image image;
  image.width = dims[0];
  image.height = dims[1];
  image.rgb.resize(static_cast<std::size_t>(3) * static_cast<std::size_t>(dims[0]) * static_cast<std::size_t>(dims[1]));
  const auto* source = static_cast<const std::uint8_t*>(frame->GetScalarPointer());
  const std::size_t row_bytes = static_cast<std::size_t>(3) * static_cast<std::size_t>(dims[0]);
  for (int y = 0; y < dims[1]; ++y)  // VTK's rows run from the bottom
    std::memcpy(image.rgb.data() + static_cast<std::size_t>(y) * row_bytes,
                source + static_cast<std::size_t>(dims[1] - 1 - y) * row_bytes, row_bytes);
  return image;
}

Image render_scene(const Scene& scene, const ShadowResult& result, const RenderOptions& options) {
  RenderOptions adjusted = options;
  adjusted.shade.image_height = options.height;
  const std::vector<OverlayCell> cells = overlay_fragments(scene, result);
  const ColouredMesh mesh = shade_cells(scene, cells, adjusted.shade);
  Image image = render_mesh(mesh, adjusted, make_decorations(scene, adjusted, mesh.exposure));
  image.exposure = mesh.exposure;
  return image;
}

std::string encode_png(const Image& image) {
  vtkNew<vtkImageData> data;
  data->SetDimensions(image.width, image.height, 1);
  data->AllocateScalars(VTK_UNSIGNED_CHAR, 3);
  auto* target = static_cast<std::uint8_t*>(data->GetScalarPointer());
  const std::size_t row_bytes = static_cast<std::size_t>(3) * static_cast<std::size_t>(image.width);
  for (int y = 0; y < image.height; ++y)
    std::memcpy(target + static_cast<std::size_t>(image.height - 1 - y) * row_bytes,
                image.rgb.data() + static_cast<std::size_t>(y) * row_bytes, row_bytes);
  // Into memory: libpng then never meets a failing file, whose errors it would print on stderr
  // itself (besides ours); the file is written by write_file_staged, checked.
  vtkNew<vtkPNGWriter> writer;
  vtkNew<detail::VtkErrorCapture> errors;  // a failure becomes one RenderError line
  writer->AddObserver(vtkCommand::ErrorEvent, errors);
  writer->WriteToMemoryOn();
  writer->SetInputData(data);
  writer->Write();
  vtkUnsignedCharArray* bytes = writer->GetResult();
  if (writer->GetErrorCode() != 0 || !errors->message().empty() || bytes == nullptr ||
      bytes->GetNumberOfValues() == 0) {
    std::string reason = errors->reason();
    for (char& c : reason)
      if (c == '\n' || c == '\r') c = ' ';
    throw RenderError("could not encode the PNG image" + (reason.empty() ? std::string() : ": " + reason));
  }
  return {reinterpret_cast<const char*>(bytes->GetPointer(0)), static_cast<std::size_t>(bytes->GetNumberOfValues())};
}

void write_png(const Image& image, const std::filesystem::path& path) {
  const std::string png = encode_png(image);
  write_file_staged(path, [&](std::ostream& out) { out.write(png.data(), static_cast<std::streamsize>(png.size())); });
}

}  // namespace shadow::render
