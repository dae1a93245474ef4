// eye_strips.cpp: the bands under the arena: both eyes' 1-D images as colour strips, and the
// status line with the stereo fix and the touch forces.
#include "view/render_internal.h"

#include <algorithm>

namespace roger::picture {
namespace {

const char* const kEyeName[2] = {"left eye", "right eye"};
const char* const kTouchName[kTactileCount] = {"body", "left hand", "right hand"};

// ---- images
// --------------------------------------------------------------------------------------

// An eye-frame angle in words: "12.3° left".
std::string bearing_text(double angle) {
  const double deg = angle * 180.0 / kPi;
  if (std::fabs(deg) < 0.05) return "straight ahead";
  return format("%.1f\u00b0 ", std::fabs(deg)) + (deg > 0 ? "left" : "right");
}

// Where one eye's strip goes: its left end and width, one cell's width, and its top and height.
struct StripBox {
  double sx, sw, cw;
  double st_top, st_h;
  int pixels;
  double half_fov;  // rad: the angle of each end from the optical axis

  // The x of image coordinate u (the last pixel at the left end).
  double x_of(double u) const { return sx + (pixels - 0.5 - u) * cw; }
};

// The row above the strip: the eye's name on the left, what it sees on the right.
void draw_strip_label(cairo_t* cr, const Layout& l, const Sighting& s, int side,
                      const StripBox& b, double label_base) {
  TextStyle name;
  name.size = 12;
  name.bold = true;
  name.colour = kEyeColour[side];
  text(cr, l, kEyeName[side], b.sx, label_base, name);
  TextStyle info;
  info.size = 11;
  info.colour = kFaintInk;
  info.align = 1.0;
  const std::string seen =
      s.seen ? format("stimulus at pixel %.1f (extent %.1f\u2013%.1f), ", s.u, s.u_lo, s.u_hi) +
                   bearing_text(s.bearing)
             : std::string("stimulus not seen");
  text(cr, l, seen, b.sx + b.sw, label_base, info);
}

// The image's cells in their colours, and the strip's outline.
void draw_strip_cells(cairo_t* cr, const Layout& l, const EyeImage& img, const StripBox& b) {
  // Cell edges are rounded to whole device pixels and shared by neighbours, so there are neither
  // anti-aliased seams between cells nor gaps.
  cairo_save(cr);
  cairo_set_antialias(cr, CAIRO_ANTIALIAS_NONE);
  for (int i = b.pixels - 1; i >= 0; --i) {
    const double x0 = std::round(b.x_of(i + 0.5)), x1 = std::round(b.x_of(i - 0.5));
    cairo_rectangle(cr, x0, std::round(b.st_top), x1 - x0,
                    std::round(b.st_top + b.st_h) - std::round(b.st_top));
    set(cr, rgb(img.colour[i]));
    cairo_fill(cr);
  }
  cairo_restore(cr);
  cairo_rectangle(cr, b.sx, b.st_top, b.sw, b.st_h);
  set(cr, kInk);
  cairo_set_line_width(cr, 1.0 * l.u);
  cairo_stroke(cr);
}

// Angle ticks under the strip every eighth of its width, labelled at both ends and the centre.
void draw_strip_ticks(cairo_t* cr, const Layout& l, const StripBox& b) {
  const double sx = b.sx, sw = b.sw, st_top = b.st_top, st_h = b.st_h;
  set(cr, kFaintInk);
  for (int k = 0; k <= 8; ++k) {
    const double x = sx + sw * k / 8.0;
    cairo_move_to(cr, x, st_top + st_h);
    cairo_line_to(cr, x, st_top + st_h + (k % 4 == 0 ? 5 : 3) * l.u);
    cairo_stroke(cr);
  }
  TextStyle tick;
  tick.size = 10;
  tick.colour = kFaintInk;
  const double tick_base = st_top + st_h + 16 * l.u;
  const double degrees = b.half_fov * 180.0 / M_PI;
  tick.align = 0.0;
  text(cr, l, format("%.0f\u00b0 left (pixel %d)", degrees, b.pixels - 1), sx, tick_base, tick);
  tick.align = 0.5;
  text(cr, l, "ahead", sx + 0.5 * sw, tick_base, tick);
  tick.align = 1.0;
  text(cr, l, format("(pixel 0) %.0f\u00b0 right", degrees), sx + sw, tick_base, tick);
}

// The detected stimulus bracketed on the strip, with a notch over its centre.
void draw_stimulus_bracket(cairo_t* cr, const Layout& l, const Sighting& s, const StripBox& b) {
  const double st_top = b.st_top, st_h = b.st_h;
  const double xa = b.x_of(std::max(s.u_hi, s.u_lo)), xb = b.x_of(std::min(s.u_hi, s.u_lo));
  const double pad = 3 * l.u;
  for (int pass = 0; pass < 2; ++pass) {
    set(cr, pass == 0 ? kWhite : kInk);
    cairo_set_line_width(cr, (pass == 0 ? 4.0 : 1.8) * l.u);
    cairo_rectangle(cr, xa, st_top - pad, std::max(xb - xa, 1.0 * l.u), st_h + 2 * pad);
    cairo_stroke(cr);
  }
  // A notch above the centre, where the bearing is taken.
  const double xc = b.x_of(s.u);
  cairo_move_to(cr, xc, st_top - pad);
  cairo_line_to(cr, xc - 4 * l.u, st_top - pad - 6 * l.u);
  cairo_line_to(cr, xc + 4 * l.u, st_top - pad - 6 * l.u);
  cairo_close_path(cr);
  set(cr, kInk);
  cairo_fill(cr);
}

}  // namespace

// One eye's image as a strip of one cell per pixel. The last pixel looks furthest left, so it is
// drawn at the left end: the strip reads like the view from behind the eye. The detected stimulus
// is bracketed.
void draw_eye_strip(cairo_t* cr, const Layout& l, const Senses& senses, int side, double top) {
  const int pixels = senses.image[side].pixels();
  const double sx = l.block_x, sw = l.block_w;
  const double cw = sw / pixels;
  const double label_base = top + 14 * l.u;
  const double st_top = top + 22 * l.u, st_h = 24 * l.u;
  const StripBox b{sx, sw, cw, st_top, st_h, pixels, senses.image[side].camera.half_fov};

  const Sighting& s = senses.stimulus[side];
  draw_strip_label(cr, l, s, side, b, label_base);
  draw_strip_cells(cr, l, senses.image[side], b);
  draw_strip_ticks(cr, l, b);
  if (s.seen && std::isfinite(s.u_lo) && std::isfinite(s.u_hi) && std::isfinite(s.u))
    draw_stimulus_bracket(cr, l, s, b);
}

// One line under everything: the stereo fix and the three touch sensors, in numbers.
void draw_status(cairo_t* cr, const Layout& l, const Senses& senses) {
  const double y = l.status_top + 20 * l.u;
  TextStyle st;
  st.size = 11;
  st.colour = kInk;
  std::string stereo = "stereo fix: none";
  if (senses.stereo_valid && finite(senses.stimulus_world))
    stereo =
        format("stereo fix: (%.2f, %.2f) m", senses.stimulus_world.x(), senses.stimulus_world.y());
  text(cr, l, stereo, l.block_x, y, st);
  std::string touch = "touch:";
  for (int t = 0; t < kTactileCount; ++t) {
    const Touch& c = senses.touch[t];
    touch += std::string(t ? ",  " : "  ") + kTouchName[t] + " ";
    touch += c.contact ? format("%.1f N", c.force) : std::string("\u2013");
  }
  st.align = 1.0;
  st.colour = senses.touch[0].contact || senses.touch[1].contact || senses.touch[2].contact
                  ? kContact
                  : kInk;
  text(cr, l, touch, l.block_x + l.block_w, y, st);
}

}  // namespace roger::picture
