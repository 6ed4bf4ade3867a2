// SPDX-License-Identifier: GPL-3.0-or-later
// `shadow render SCENE -o view.svg|view.pdf`: the exact vector view written as SVG (by hand:
// the format is a few elements) or PDF (cairo). Needs no X display, unlike the PNG.
#include <shadow/render/vector_drawing.hpp>

#include <shadow/render/camera.hpp>
#include <shadow/render/render_image.hpp>
#include <shadow/render/shaded_mesh.hpp>

#include <shadow/shadow.hpp>

#ifdef LIBSHADOW_HAVE_CAIRO
#include <cairo-pdf.h>
#include <cairo.h>
#endif

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>

namespace shadow::render {
namespace {

double srgb(double linear) {
  const double c = std::clamp(linear, 0.0, 1.0);
  return c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055;
}

std::string hex_colour(const glm::dvec3& c) {
  char text[8];
  auto byte = [](double v) { return static_cast<int>(std::lround(std::clamp(v, 0.0, 1.0) * 255.0)); };
  std::snprintf(text, sizeof text, "#%02x%02x%02x", byte(c.x), byte(c.y), byte(c.z));
  return text;
}

std::string xml_text(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default:
        // Control characters are not allowed in XML 1.0 (tab, newline and return are).
        if (static_cast<unsigned char>(c) < 0x20 && c != '\t' && c != '\n' && c != '\r') out += ' ';
        else out += c;
    }
  }
  return out;
}

/// Shortest text that reads back as the same double: 17 significant digits always do.
std::string number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", v == 0.0 ? 0.0 : v);  // no "-0"
  return text;
}

constexpr glm::dvec3 kBackground{0.93, 0.95, 0.98};  // as displayed: the PNG's pale sky
constexpr glm::dvec3 kEdge{0.15, 0.15, 0.18};
constexpr double kEdgeWidth = 0.5;  // pixels (points in the PDF)

}  // namespace

bool is_vector_output(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext == ".svg" || ext == ".pdf";
}

glm::dvec3 piece_colour(const Scene& scene, const VectorView& view, const ViewPiece& piece,
                        const VectorStyle& style) {
  const std::size_t mesh = scene.faces[piece.face_id].mesh;
  const glm::dvec3 base = piece.face_id < style.face_colours.size() ? style.face_colours[piece.face_id]
                          : mesh < style.mesh_colours.size()        ? style.mesh_colours[mesh]
                                                                    : scene.material_of(piece.face_id).color;
  // Lit: the material's colour a little darkened, so that white stays apart from the sky;
  // shadowed: a third of it. Without a light every piece is drawn as lit.
  const double scale = !view.light_id || piece.lit ? 0.8 : 0.18;
  return {srgb(base.x * scale), srgb(base.y * scale), srgb(base.z * scale)};
}

void write_svg(const Scene& scene, const VectorView& view, const std::filesystem::path& path,
               const VectorStyle& style) {
  std::ostringstream out;
  const int w = view.frame.width, h = view.frame.height;
  out << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      << "<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" width=\"" << w << "\" height=\"" << h
      << "\" viewBox=\"0 0 " << w << ' ' << h << "\">\n"
      << "<title>" << xml_text(style.title) << "</title>\n"
      << "<rect x=\"0\" y=\"0\" width=\"" << w << "\" height=\"" << h << "\" fill=\"" << hex_colour(kBackground)
      << "\"/>\n";
  // Pieces are interior-disjoint in the image: any order draws the same picture.
  std::size_t k = 0;
  while (k < view.pieces.size()) {
    const std::size_t face = view.pieces[k].face_id;
    const Mesh& mesh = scene.meshes[scene.faces[face].mesh];
    out << "<g id=\"face-" << face << "\" data-face-id=\"" << face << "\" data-mesh=\"" << xml_text(mesh.name)
        << "\" data-back=\"" << (view.pieces[k].back ? 1 : 0) << "\"";
    out << " stroke-width=\"" << kEdgeWidth << "\" stroke-linejoin=\"round\"";
    if (style.edges) out << " stroke=\"" << hex_colour(kEdge) << "\"";
    out << ">\n";
    for (; k < view.pieces.size() && view.pieces[k].face_id == face; ++k) {
      const ViewPiece& p = view.pieces[k];
      const std::string fill = hex_colour(piece_colour(scene, view, p, style));
      out << "<path data-lit=\"" << (p.lit ? 1 : 0) << "\" fill=\"" << fill << "\"";
      // Without edges, a half-pixel outline in the piece's own colour, as thin on screen at any
      // zoom: renderers anti-alias each piece alone and leave the background showing through
      // the seam between two pieces that touch.
      if (!style.edges) out << " stroke=\"" << fill << "\" vector-effect=\"non-scaling-stroke\"";
      out << " d=\"";
      for (std::size_t v = 0; v < p.image.size(); ++v)
        out << (v == 0 ? "M" : " L") << number(p.image[v].x) << ' ' << number(p.image[v].y);
      out << " Z\"/>\n";
    }
    out << "</g>\n";
  }
  out << "</svg>\n";
  const std::string text = out.str();
  write_file_staged(path, [&](std::ostream& file) { file.write(text.data(), static_cast<std::streamsize>(text.size())); });
}

void write_pdf(const Scene& scene, const VectorView& view, const std::filesystem::path& path,
               const VectorStyle& style) {
#ifdef LIBSHADOW_HAVE_CAIRO
  // Into memory, then written like every other output (write_file_staged): cairo writing the
  // file itself reported success on a full disk and left the cut file under its final name.
  std::string pdf;
  const cairo_write_func_t append = [](void* closure, const unsigned char* data, unsigned int length) {
    static_cast<std::string*>(closure)->append(reinterpret_cast<const char*>(data), length);
    return CAIRO_STATUS_SUCCESS;
  };
  cairo_surface_t* surface = cairo_pdf_surface_create_for_stream(append, &pdf, view.frame.width, view.frame.height);
  auto fail = [&](cairo_status_t status) {
    cairo_surface_destroy(surface);
    throw RenderError("cannot draw " + path.string() + ": " + cairo_status_to_string(status));
  };
  if (cairo_surface_status(surface) != CAIRO_STATUS_SUCCESS) fail(cairo_surface_status(surface));
  cairo_pdf_surface_set_metadata(surface, CAIRO_PDF_METADATA_TITLE, style.title.c_str());
  cairo_pdf_surface_set_metadata(surface, CAIRO_PDF_METADATA_CREATOR, (std::string("libshadow ") + version()).c_str());
  cairo_t* cr = cairo_create(surface);
  cairo_set_source_rgb(cr, kBackground.x, kBackground.y, kBackground.z);
  cairo_paint(cr);
  cairo_set_line_width(cr, kEdgeWidth);
  cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
  for (const ViewPiece& p : view.pieces) {
    if (p.image.empty()) continue;
    cairo_new_path(cr);
    cairo_move_to(cr, p.image[0].x, p.image[0].y);
    for (std::size_t v = 1; v < p.image.size(); ++v) cairo_line_to(cr, p.image[v].x, p.image[v].y);
    cairo_close_path(cr);
    const glm::dvec3 c = piece_colour(scene, view, p, style);
    cairo_set_source_rgb(cr, c.x, c.y, c.z);
    // The seams between touching pieces hidden as in the SVG, by an outline in the fill's
    // colour (a quarter point wide: PDF has no non-scaling stroke), or dark edges.
    cairo_fill_preserve(cr);
    if (style.edges) {
      cairo_set_source_rgb(cr, kEdge.x, kEdge.y, kEdge.z);
      cairo_set_line_width(cr, kEdgeWidth);
    } else {
      cairo_set_line_width(cr, 0.25);
    }
    cairo_stroke(cr);
  }
  const cairo_status_t drawn = cairo_status(cr);
  cairo_destroy(cr);
  if (drawn != CAIRO_STATUS_SUCCESS) fail(drawn);
  cairo_surface_finish(surface);  // completes the document in `pdf`
  if (cairo_surface_status(surface) != CAIRO_STATUS_SUCCESS) fail(cairo_surface_status(surface));
  cairo_surface_destroy(surface);
  write_file_staged(path, [&](std::ostream& file) { file.write(pdf.data(), static_cast<std::streamsize>(pdf.size())); });
#else
  (void)scene;
  (void)view;
  (void)style;
  throw RenderError("cannot write " + path.string() +
                    ": this shadow was built without cairo (install libcairo2-dev and build again)");
#endif
}

}  // namespace shadow::render
