// render.cpp: a world picture laid out (metres to pixels), its header and text, the whole frame
// drawn part by part (the parts live in world_picture.cpp, robot_picture.cpp and eye_strips.cpp),
// and written as PNG or SVG.
#include "view/render.h"
#include "view/render_internal.h"

#include "core/fileio.h"
#include "view/cairo_file.h"
#include "view/ink.h"

#include <cairo-svg.h>
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <random>
#include <sstream>

#include "core/error.h"
#include "senses/senses.h"
#include "core/shape.h"
#include "core/text.h"

namespace roger {

// The picture's parts (render_internal.h), used by the layout and the public functions below.
using namespace picture;

namespace {

// ---- layout
// ----------------------------------------------------------------------------------------

// Height of everything but the arena, in design units.
double chrome_height(const RenderOptions& o) {
  return kTopBand + kBelowArena + (o.show_images ? 2 * kEyeBlock : 0) +
         (o.show_status ? kStatusBand : 0) + kBottomBand;
}

// A picture of an empty or non-finite arena would be meaningless (and the layout would divide by
// 0).
void check_arena(const ArenaSpec& a) {
  if (!std::isfinite(a.xmin) || !std::isfinite(a.xmax) || !std::isfinite(a.ymin) ||
      !std::isfinite(a.ymax) || !(a.xmax > a.xmin) || !(a.ymax > a.ymin))
    throw Error("render: the arena x in [" + format("%g", a.xmin) + ", " + format("%g", a.xmax) +
                "], y in [" + format("%g", a.ymin) + ", " + format("%g", a.ymax) +
                "] is empty or not finite");
}

// Arena extents, kept positive so a degenerate arena cannot divide by zero before it is reported.
double span_x(const ArenaSpec& a) { return std::max(a.xmax - a.xmin, 1e-3); }
double span_y(const ArenaSpec& a) { return std::max(a.ymax - a.ymin, 1e-3); }

// Fits the arena into whatever is left of width x height after the furniture, keeping metres
// square.
Layout make_layout(const WorldSpec& spec, const RenderOptions& o, double width, double height) {
  Layout l;
  l.u = width / 1000.0;
  const ArenaSpec& a = spec.arena;
  check_arena(a);
  l.xmin = a.xmin, l.xmax = a.xmax, l.ymin = a.ymin, l.ymax = a.ymax;
  const double avail_w = std::max(width - (kLeftBand + kRightBand) * l.u, 1.0);
  const double avail_h = std::max(height - chrome_height(o) * l.u, 1.0);
  l.scale = std::min(avail_w / span_x(a), avail_h / span_y(a));
  l.aw = l.scale * span_x(a);
  l.ah = l.scale * span_y(a);
  l.x0 = kLeftBand * l.u + 0.5 * (avail_w - l.aw);
  // Spare height (a picture taller than the layout needs) is shared above and below.
  const double slack = std::max(0.0, avail_h - l.ah);
  l.y0 = kTopBand * l.u + 0.5 * slack;
  l.block_x = kLeftBand * l.u;
  l.block_w = avail_w;
  l.eyes_top = l.y0 + l.ah + kBelowArena * l.u;
  l.status_top = l.eyes_top + (o.show_images ? 2 * kEyeBlock * l.u : 0);
  return l;
}

}  // namespace

namespace picture {

// ---- text
// ----------------------------------------------------------------------------------------

// Width of a text in device pixels.
double text_width(cairo_t* cr, const Layout& l, const std::string& s, const TextStyle& st) {
  cairo_select_font_face(cr, "DejaVu Sans", CAIRO_FONT_SLANT_NORMAL,
                         st.bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, st.size * l.u);
  cairo_text_extents_t e;
  cairo_text_extents(cr, s.c_str(), &e);
  return e.x_advance;
}

// Draws text with its baseline at y; returns the width drawn.
double text(cairo_t* cr, const Layout& l, const std::string& s, double x, double y,
            const TextStyle& st) {
  const double w = text_width(cr, l, s, st);
  cairo_move_to(cr, x - st.align * w, y);
  if (st.halo) {
    cairo_text_path(cr, s.c_str());
    set(cr, kWhite, 0.85);
    cairo_set_line_width(cr, 3.0 * l.u);
    cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
    cairo_stroke_preserve(cr);
    set(cr, st.colour);
    cairo_fill(cr);
  } else {
    set(cr, st.colour);
    cairo_show_text(cr, s.c_str());
  }
  return w;
}

void separate_labels(std::vector<LabelBox>& boxes, int tries) {
  const auto overlaps = [](const LabelBox& a, const LabelBox& b) {
    return a.x0 < b.x1 && b.x0 < a.x1 && a.y0 < b.y1 && b.y0 < a.y1;
  };
  for (size_t k = 1; k < boxes.size(); ++k) {
    LabelBox& box = boxes[k];
    const double height = box.y1 - box.y0;
    for (int move = 0; move < tries; ++move) {
      if (std::none_of(boxes.begin(), boxes.begin() + long(k), [&](const LabelBox& b) { return overlaps(box, b); }))
        break;
      box.y0 += height;
      box.y1 += height;
    }
  }
}

}  // namespace picture

namespace {

// `s` cut to fit `room` (with an ellipsis), whole when it fits; "" when not even the ellipsis does.
std::string fitted(cairo_t* cr, const Layout& l, const std::string& s, const TextStyle& st, double room) {
  if (text_width(cr, l, s, st) <= room) return s;
  std::string cut = s;
  while (!cut.empty()) {
    cut.pop_back();
    while (!cut.empty() && (static_cast<unsigned char>(cut.back()) & 0xC0) == 0x80) cut.pop_back();  // UTF-8
    if (text_width(cr, l, cut + "\u2026", st) <= room) return cut + "\u2026";
  }
  return "";
}

// Title, scenario and seed on the left, the time on the right; in a narrow picture the title is
// cut and the scenario line left out rather than drawn over the time.
void draw_header(cairo_t* cr, const Layout& l, const WorldSpec& spec, const Frame& frame,
                 const RenderOptions& o, double width) {
  const double y = 26 * l.u, gap = 12 * l.u;
  TextStyle st;
  st.size = 16;
  TextStyle time = st;
  time.align = 1.0;
  const std::string clock = format("t = %.2f s", frame.time);
  const double time_left = width - kRightBand * l.u - text_width(cr, l, clock, time) - gap;
  st.bold = true;
  double x = kLeftBand * l.u;
  if (!o.title.empty()) x += text(cr, l, fitted(cr, l, o.title, st, time_left - x), x, y, st) + gap;
  if (!spec.scenario.empty()) {
    TextStyle sub;
    sub.size = 12;
    sub.colour = kFaintInk;
    const std::string line = "scenario " + spec.scenario + ", seed " + std::to_string(spec.seed);
    if (text_width(cr, l, line, sub) <= time_left - x) text(cr, l, line, x, y, sub);
  }
  text(cr, l, clock, width - kRightBand * l.u, y, time);
}

// ---- files
// ---------------------------------------------------------------------------------------

enum class Format { kPng, kSvg };

// The file format named by path's extension, or an Error naming the two accepted ones.
Format format_of(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  const std::string lower = lower_ascii(ext);
  if (lower == ".png") return Format::kPng;
  if (lower == ".svg") return Format::kSvg;
  throw Error(
      "render: cannot write picture '" + path + "': " +
      (ext.empty() ? std::string("it has no extension") : "unknown extension '" + ext + "'") +
      "; use .png or .svg");
}

// Makes a surface of the right kind, lets paint draw on it, and writes it atomically to path.
template <class Paint>
void write_picture(const std::string& path, long width, long height, Paint paint) {
  const Format format = format_of(path);
  if (width < 1 || height < 1 || width > kMaxPicturePixels || height > kMaxPicturePixels) {
    std::ostringstream os;
    os << "render: cannot write picture '" << path << "': a " << width << " x " << height
       << " picture is outside 1 to " << kMaxPicturePixels << " pixels per side";
    throw Error(os.str());
  }
  make_parent_folder(path, "render: cannot write picture");  // as every other output's (write_file_atomic)
  AtomicFile file(path, "render: cannot write picture");
  Canvas canvas;
  if (format == Format::kSvg) {
    canvas.surface = cairo_svg_surface_create_for_stream(&cairo_write_to_file, &file, width, height);
    cairo_svg_surface_set_document_unit(canvas.surface, CAIRO_SVG_UNIT_PX);
  } else {
    canvas.surface = cairo_image_surface_create(CAIRO_FORMAT_ARGB32, int(width), int(height));
  }
  check_cairo(file, cairo_surface_status(canvas.surface));
  canvas.cr = cairo_create(canvas.surface);
  paint(canvas.cr);
  check_cairo(file, cairo_status(canvas.cr));
  if (format == Format::kPng) {
    cairo_surface_flush(canvas.surface);
    check_cairo(file, cairo_surface_write_to_png_stream(canvas.surface, &cairo_write_to_file, &file));
  } else {
    cairo_destroy(canvas.cr);  // the SVG is serialised when the surface finishes
    canvas.cr = nullptr;
    cairo_surface_finish(canvas.surface);
    check_cairo(file, cairo_surface_status(canvas.surface));
  }
  file.commit();
}

// Keeps pictures within sizes cairo can make and a person can read.
void check_width(const RenderOptions& o) {
  if (o.width_px < 100 || o.width_px > 16000)
    throw Error("render: width_px must be between 100 and 16000 pixels, got " +
                std::to_string(o.width_px));
}

}  // namespace

PictureSize picture_size(const WorldSpec& spec, const RenderOptions& options) {
  check_width(options);
  check_arena(spec.arena);
  const double w = options.width_px, u = w / 1000.0;
  const double scale = (w - (kLeftBand + kRightBand) * u) / span_x(spec.arena);
  const double h = scale * span_y(spec.arena) + chrome_height(options) * u;
  // Capped so an absurdly tall arena is reported by write_picture as too large, not overflowed
  // here.
  return {options.width_px, int(std::min(std::ceil(h), 1e9))};
}

void draw_frame(cairo_t* cr, const WorldSpec& spec, const Frame& frame,
                const RenderOptions& options, double width, double height) {
  const std::vector<Pose> poses = object_poses(spec, frame);
  const Layout l = make_layout(spec, options, width, height);
  cairo_save(cr);
  cairo_rectangle(cr, 0, 0, width, height);
  cairo_clip(cr);
  set(cr, kBackground);
  cairo_paint(cr);

  draw_header(cr, l, spec, frame, options, width);
  draw_arena(cr, l, spec, options);
  draw_goals(cr, l, spec);
  // The fields of view of the camera that painted the frame's images (the world model's).
  if (options.show_fields_of_view) draw_fields_of_view(cr, l, frame, frame.senses.image[kLeft].camera.half_fov);
  draw_things(cr, l, spec, poses);
  if (options.show_fields_of_view) draw_sight_lines(cr, l, frame);
  draw_robot(cr, l, frame, spec.body);
  if (options.show_fields_of_view) draw_stereo_fix(cr, l, frame.senses);
  if (options.show_labels) draw_labels(cr, l, spec, poses);
  if (options.show_contacts) draw_contacts(cr, l, frame.senses, options);
  if (options.show_images)
    for (int side = 0; side < 2; ++side)
      draw_eye_strip(cr, l, frame.senses, side, l.eyes_top + side * kEyeBlock * l.u);
  if (options.show_status) draw_status(cr, l, frame.senses);
  cairo_restore(cr);
}

Vec2 picture_point(const WorldSpec& spec, const RenderOptions& options, double width, double height,
                   const Vec2& world) {
  const Layout l = make_layout(spec, options, width, height);
  return {l.px(world.x()), l.py(world.y())};
}

void render_frame(const WorldSpec& spec, const Frame& frame, const std::string& path,
                  const RenderOptions& options) {
  format_of(path);  // a bad extension is reported before any drawing
  const PictureSize size = picture_size(spec, options);
  write_picture(path, size.width, size.height, [&](cairo_t* cr) {
    draw_frame(cr, spec, frame, options, size.width, size.height);
  });
}

RgbPicture render_rgb(const WorldSpec& spec, const Frame& frame, const RenderOptions& options) {
  const PictureSize size = picture_size(spec, options);
  if (size.height > kMaxPicturePixels)
    throw Error("render: a " + std::to_string(size.width) + " x " + std::to_string(size.height) +
                " picture is outside 1 to " + std::to_string(kMaxPicturePixels) + " pixels per side");
  Canvas canvas;
  canvas.surface = cairo_image_surface_create(CAIRO_FORMAT_RGB24, size.width, size.height);
  canvas.cr = cairo_create(canvas.surface);
  draw_frame(canvas.cr, spec, frame, options, size.width, size.height);
  if (cairo_status(canvas.cr) != CAIRO_STATUS_SUCCESS)
    throw Error(std::string("render: cannot draw the picture: ") + cairo_status_to_string(cairo_status(canvas.cr)));
  cairo_surface_flush(canvas.surface);
  RgbPicture p{size.width, size.height, std::vector<uint8_t>(size_t(size.width) * size_t(size.height) * 3)};
  const unsigned char* data = cairo_image_surface_get_data(canvas.surface);
  const int stride = cairo_image_surface_get_stride(canvas.surface);
  uint8_t* out = p.pixels.data();
  for (int y = 0; y < size.height; ++y) {
    const uint32_t* row = reinterpret_cast<const uint32_t*>(data + size_t(y) * size_t(stride));
    for (int x = 0; x < size.width; ++x, out += 3) {  // RGB24: 0x00RRGGBB in native byte order
      out[0] = uint8_t(row[x] >> 16);
      out[1] = uint8_t(row[x] >> 8);
      out[2] = uint8_t(row[x]);
    }
  }
  return p;
}

void render_frames(const WorldSpec& spec, const std::vector<Frame>& frames, const std::string& path,
                   const RenderOptions& options, int columns) {
  format_of(path);
  if (frames.empty()) throw Error("render: no frames to draw into '" + path + "'");
  if (columns < 0)
    throw Error("render: columns must be 0 (one row) or more, got " + std::to_string(columns));
  const PictureSize panel = picture_size(spec, options);
  const int n = int(frames.size());
  const int cols = columns == 0 ? n : std::min(columns, n);
  const int rows = (n + cols - 1) / cols;
  const long width = long(panel.width) * cols, height = long(panel.height) * rows;
  write_picture(path, width, height, [&](cairo_t* cr) {
    for (int i = 0; i < n; ++i) {
      cairo_save(cr);
      cairo_translate(cr, double(i % cols) * panel.width, double(i / cols) * panel.height);
      draw_frame(cr, spec, frames[i], options, panel.width, panel.height);
      cairo_restore(cr);
    }
  });
}

}  // namespace roger
