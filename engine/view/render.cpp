#include "view/render.h"

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

namespace roger {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kHalfFov = kPi / 4;  // the eyes see +-45 degrees about their axis

// The picture's furniture, in design units (one unit is a pixel of a 1000-pixel-wide picture), so
// every picture size has the same proportions.
constexpr double kTopBand = 48;   // title and time
constexpr double kLeftBand = 60;  // y tick labels
constexpr double kRightBand = 26;
constexpr double kBelowArena = 38;  // x tick labels
constexpr double kEyeBlock = 72;    // one eye: label row, strip, angle labels
constexpr double kStatusBand = 30;  // stereo fix and touch forces
constexpr double kBottomBand = 8;
constexpr double kWall = 8;  // drawn wall thickness (the walls' real thickness is not modelled)

using namespace ink;

// The palette: Roger is light steel with dark arms so he never looks like a grey obstacle; each eye
// has its own colour, used for its wedge, its sight line and its image strip's label.
const Rgb kBackground = rgb(255, 255, 255);
const Rgb kFloor = rgb(248, 247, 242);
const Rgb kRobotBody = rgb(214, 222, 234);
const Rgb kRobotOutline = rgb(38, 44, 56);
const Rgb kArm = rgb(66, 74, 90);
const Rgb kWheel = rgb(45, 45, 50);
const Rgb kEyeColour[2] = {rgb(30, 100, 220), rgb(232, 118, 18)};
const Rgb kContact = rgb(205, 0, 145);
const char* const kEyeName[2] = {"left eye", "right eye"};
const char* const kTouchName[kTactileCount] = {"body", "left hand", "right hand"};

bool finite(const Vec2& p) { return std::isfinite(p.x()) && std::isfinite(p.y()); }
bool finite(const Pose& p) {
  return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.theta);
}

// printf-style formatting of numbers for labels (std::format is C++20).
template <class... Args>
std::string format(const char* fmt, Args... args) {
  char buf[160];
  std::snprintf(buf, sizeof buf, fmt, args...);
  return buf;
}

// Where everything goes in device space. World y points up, device y down: the flip lives here.
struct Layout {
  double u = 1;                           // device pixels per design unit
  double scale = 1;                       // device pixels per metre
  double x0 = 0, y0 = 0, aw = 0, ah = 0;  // the arena floor rectangle
  double xmin = 0, xmax = 0, ymin = 0, ymax = 0;
  double block_x = 0, block_w = 0;  // horizontal extent of the strips and status line
  double eyes_top = 0;              // top of the two eye blocks
  double status_top = 0;            // top of the status line

  double px(double x) const { return x0 + (x - xmin) * scale; }
  double py(double y) const { return y0 + (ymax - y) * scale; }
  void move_to(cairo_t* cr, const Vec2& p) const { cairo_move_to(cr, px(p.x()), py(p.y())); }
  void line_to(cairo_t* cr, const Vec2& p) const { cairo_line_to(cr, px(p.x()), py(p.y())); }
};

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

// ---- text
// ----------------------------------------------------------------------------------------

struct TextStyle {
  double size = 12;  // design units
  Rgb colour = kInk;
  bool bold = false;
  double align = 0.0;  // 0 left, 0.5 centre, 1 right of x
  bool halo = false;   // a white outline, for text over busy drawing
};

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

// ---- shapes
// --------------------------------------------------------------------------------------

// Adds a world disk to the current path as its own closed sub-path.
void disk_path(cairo_t* cr, const Layout& l, const Vec2& c, double r) {
  cairo_new_sub_path(cr);
  cairo_arc(cr, l.px(c.x()), l.py(c.y()), r * l.scale, 0, 2 * kPi);
  cairo_close_path(cr);
}

// Fills and outlines every part of a shape placed at pose.
void draw_shape(cairo_t* cr, const Layout& l, const Shape& shape, const Pose& pose, Rgb fill,
                double alpha) {
  if (!finite(pose)) return;
  const Rgb edge = darker(fill, 0.6);
  auto paint = [&] {
    set(cr, fill, alpha);
    cairo_fill_preserve(cr);
    set(cr, edge, std::min(1.0, alpha + 0.1));
    cairo_set_line_width(cr, 1.5 * l.u);
    cairo_stroke(cr);
  };
  for (const Polygon& poly : shape.polygons) {
    if (poly.vertices.size() < 3) continue;
    cairo_new_path(cr);
    l.move_to(cr, to_world(pose, poly.vertices[0]));
    for (size_t i = 1; i < poly.vertices.size(); ++i)
      l.line_to(cr, to_world(pose, poly.vertices[i]));
    cairo_close_path(cr);
    paint();
  }
  for (const Disk& d : shape.disks) {
    cairo_new_path(cr);
    disk_path(cr, l, to_world(pose, d.center), d.radius);
    paint();
  }
}

// A short dark tick along the body's +x axis, away from its centre, so rotation is visible even
// for a ball (and the centre pixel keeps the object's own colour).
void draw_orientation_tick(cairo_t* cr, const Layout& l, const Shape& shape, const Pose& pose,
                           Rgb colour) {
  if (!finite(pose)) return;
  const double r = shape_bounding_radius(shape);
  if (!(r > 0)) return;
  cairo_new_path(cr);
  l.move_to(cr, to_world(pose, Vec2(0.5 * r, 0)));
  l.line_to(cr, to_world(pose, Vec2(0.85 * r, 0)));
  set(cr, darker(colour, 0.55), 0.9);
  cairo_set_line_width(cr, 2.0 * l.u);
  cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
  cairo_stroke(cr);
}

// A name centred just above a shape's bounding circle.
void label_above(cairo_t* cr, const Layout& l, const std::string& name, const Vec2& centre,
                 double radius, Rgb colour) {
  if (name.empty() || !finite(centre)) return;
  TextStyle st;
  st.size = 11;
  st.colour = colour;
  st.align = 0.5;
  st.halo = true;
  text(cr, l, name, l.px(centre.x()), l.py(centre.y() + radius) - 4 * l.u, st);
}

// ---- arena
// ---------------------------------------------------------------------------------------

// A round tick spacing giving at most about ten intervals over span.
double nice_step(double span) {
  const double raw = span / 10.0;
  const double p = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 2.5, 5.0, 10.0})
    if (m * p >= raw - 1e-12) return m * p;
  return 10 * p;
}

// A tick value without trailing zeros or a negative zero.
std::string tick_label(double v) {
  if (std::fabs(v) < 1e-9) v = 0;
  return format("%g", v);
}

// Walls, floor, the origin axes (or the whole grid) and the metric scale on two sides.
void draw_arena(cairo_t* cr, const Layout& l, const WorldSpec& spec, const RenderOptions& o) {
  const double w = kWall * l.u;
  // Walls: a band around the floor, so the floor itself is exactly the arena.
  cairo_rectangle(cr, l.x0 - w, l.y0 - w, l.aw + 2 * w, l.ah + 2 * w);
  set(cr, rgb(spec.arena.wall_colour));
  cairo_fill(cr);
  cairo_rectangle(cr, l.x0 - w, l.y0 - w, l.aw + 2 * w, l.ah + 2 * w);
  set(cr, darker(rgb(spec.arena.wall_colour), 0.6));
  cairo_set_line_width(cr, 1.0 * l.u);
  cairo_stroke(cr);
  cairo_rectangle(cr, l.x0, l.y0, l.aw, l.ah);
  set(cr, kFloor);
  cairo_fill(cr);

  const double step = nice_step(std::max(l.xmax - l.xmin, l.ymax - l.ymin));
  const long kx0 = std::lround(std::ceil(l.xmin / step - 1e-9));
  const long kx1 = std::lround(std::floor(l.xmax / step + 1e-9));
  const long ky0 = std::lround(std::ceil(l.ymin / step - 1e-9));
  const long ky1 = std::lround(std::floor(l.ymax / step + 1e-9));

  // Floor lines: faint everywhere when asked for, and always a little stronger through the origin
  // so the world axes are easy to find.
  cairo_set_line_width(cr, 1.0 * l.u);
  for (long k = kx0; k <= kx1; ++k) {
    const bool axis = k == 0;
    if (!o.show_grid && !axis) continue;
    set(cr, kInk, axis ? 0.14 : 0.07);
    cairo_move_to(cr, l.px(k * step), l.y0);
    cairo_line_to(cr, l.px(k * step), l.y0 + l.ah);
    cairo_stroke(cr);
  }
  for (long k = ky0; k <= ky1; ++k) {
    const bool axis = k == 0;
    if (!o.show_grid && !axis) continue;
    set(cr, kInk, axis ? 0.14 : 0.07);
    cairo_move_to(cr, l.x0, l.py(k * step));
    cairo_line_to(cr, l.x0 + l.aw, l.py(k * step));
    cairo_stroke(cr);
  }

  // Ticks and metre labels outside the walls.
  TextStyle st;
  st.size = 11;
  st.colour = kFaintInk;
  set(cr, kFaintInk);
  cairo_set_line_width(cr, 1.0 * l.u);
  const double bottom = l.y0 + l.ah + w;
  for (long k = kx0; k <= kx1; ++k) {
    const double x = l.px(k * step);
    cairo_move_to(cr, x, bottom);
    cairo_line_to(cr, x, bottom + 5 * l.u);
    cairo_stroke(cr);
    st.align = 0.5;
    text(cr, l, tick_label(k * step), x, bottom + 18 * l.u, st);
  }
  const double left = l.x0 - w;
  for (long k = ky0; k <= ky1; ++k) {
    const double y = l.py(k * step);
    set(cr, kFaintInk);
    cairo_move_to(cr, left, y);
    cairo_line_to(cr, left - 5 * l.u, y);
    cairo_stroke(cr);
    st.align = 1.0;
    text(cr, l, tick_label(k * step), left - 8 * l.u, y + 4 * l.u, st);
  }
  // The unit once, in the corner where both scales meet.
  st.align = 1.0;
  st.size = 10;
  text(cr, l, "metres", left - 8 * l.u, bottom + 18 * l.u, st);
}

// ---- goals, obstacles, objects
// -------------------------------------------------------------------

// Goal regions: translucent disks with a dashed rim, drawn first because they are floor markings.
void draw_goals(cairo_t* cr, const Layout& l, const WorldSpec& spec) {
  for (const GoalRegion& g : spec.goals) {
    if (!finite(g.center) || !(g.radius > 0)) continue;
    const Rgb c = rgb(g.colour);
    cairo_new_path(cr);
    disk_path(cr, l, g.center, g.radius);
    set(cr, c, 0.3);
    cairo_fill_preserve(cr);
    const double dash[] = {6 * l.u, 4 * l.u};
    cairo_set_dash(cr, dash, 2, 0);
    set(cr, darker(c, 0.8), 0.9);
    cairo_set_line_width(cr, 1.5 * l.u);
    cairo_stroke(cr);
    cairo_set_dash(cr, nullptr, 0, 0);
  }
}

// Object poses for this frame: the frame's, or the spec's starting poses for a frame without any
// (a scenario preview before the first tick).
std::vector<Pose> object_poses(const WorldSpec& spec, const Frame& frame) {
  if (frame.objects.empty()) {
    std::vector<Pose> poses;
    for (const ObjectSpec& obj : spec.objects) poses.push_back(obj.pose);
    return poses;
  }
  if (frame.objects.size() != spec.objects.size()) {
    std::ostringstream os;
    os << "render: the frame has " << frame.objects.size()
       << " object poses but the world spec has " << spec.objects.size() << " objects";
    throw Error(os.str());
  }
  return frame.objects;
}

// Obstacles, then objects over them, each part in its own colour.
void draw_things(cairo_t* cr, const Layout& l, const WorldSpec& spec,
                 const std::vector<Pose>& poses) {
  for (const ObstacleSpec& ob : spec.obstacles)
    draw_shape(cr, l, ob.shape, ob.pose, rgb(ob.colour), 1.0);
  for (size_t i = 0; i < spec.objects.size(); ++i) {
    const ObjectSpec& obj = spec.objects[i];
    draw_shape(cr, l, obj.shape, poses[i], rgb(obj.colour), 1.0);
    draw_orientation_tick(cr, l, obj.shape, poses[i], rgb(obj.colour));
  }
}

// Names of goals, obstacles and objects, last so that nothing covers them.
void draw_labels(cairo_t* cr, const Layout& l, const WorldSpec& spec,
                 const std::vector<Pose>& poses) {
  for (const GoalRegion& g : spec.goals)
    label_above(cr, l, g.name, g.center, g.radius, darker(rgb(g.colour), 0.6));
  for (const ObstacleSpec& ob : spec.obstacles)
    label_above(cr, l, ob.name, Vec2(ob.pose.x, ob.pose.y), shape_bounding_radius(ob.shape),
                kFaintInk);
  for (size_t i = 0; i < spec.objects.size(); ++i)
    label_above(cr, l, spec.objects[i].name, Vec2(poses[i].x, poses[i].y),
                shape_bounding_radius(spec.objects[i].shape),
                darker(rgb(spec.objects[i].colour), 0.7));
}

// ---- eyes
// ----------------------------------------------------------------------------------------

// The stereo fix: a haloed cross-hair with an open centre, so the object under it stays visible and
// the gap between the estimate and the true centre can be judged.
constexpr double kFixGap = 6;  // design units
constexpr double kFixArm = 15;

void draw_stereo_fix(cairo_t* cr, const Layout& l, const Senses& senses) {
  if (!senses.stereo_valid || !finite(senses.stimulus_world)) return;
  const double x = l.px(senses.stimulus_world.x()), y = l.py(senses.stimulus_world.y());
  const double g = kFixGap * l.u, a = kFixArm * l.u;
  cairo_set_line_cap(cr, CAIRO_LINE_CAP_BUTT);  // round caps would close the gap
  for (int pass = 0; pass < 2; ++pass) {
    set(cr, pass == 0 ? kWhite : kInk, pass == 0 ? 0.9 : 1.0);
    cairo_set_line_width(cr, (pass == 0 ? 5.0 : 2.2) * l.u);
    for (const auto& d : {std::make_pair(1, 0), std::make_pair(-1, 0), std::make_pair(0, 1),
                          std::make_pair(0, -1)}) {
      cairo_move_to(cr, x + d.first * g, y + d.second * g);
      cairo_line_to(cr, x + d.first * a, y + d.second * a);
    }
    cairo_stroke(cr);
  }
  TextStyle st;
  st.size = 10;
  st.halo = true;
  text(cr, l, "stereo fix", x + a + 3 * l.u, y + 14 * l.u, st);
}

// The point length metres from `from` in the world direction angle.
Vec2 along(const Vec2& from, double angle, double length) {
  return from + length * Vec2(std::cos(angle), std::sin(angle));
}

// Each eye's +-45 degree wedge on the floor (clipped to the arena) and its dotted optical axis.
void draw_fields_of_view(cairo_t* cr, const Layout& l, const Frame& frame) {
  const double reach = std::hypot(l.xmax - l.xmin, l.ymax - l.ymin);
  cairo_save(cr);
  cairo_rectangle(cr, l.x0, l.y0, l.aw, l.ah);
  cairo_clip(cr);
  for (int side = 0; side < 2; ++side) {
    const Vec2& eye = frame.eyes[side];
    const double h = frame.eye_heading[side];
    if (!finite(eye) || !std::isfinite(h)) continue;
    cairo_new_path(cr);
    l.move_to(cr, eye);
    constexpr int kArcSteps = 32;
    for (int i = 0; i <= kArcSteps; ++i)
      l.line_to(cr, along(eye, h - kHalfFov + 2 * kHalfFov * i / kArcSteps, reach));
    cairo_close_path(cr);
    set(cr, kEyeColour[side], 0.05);
    cairo_fill(cr);
    cairo_set_line_width(cr, 1.0 * l.u);
    set(cr, kEyeColour[side], 0.35);
    for (double edge : {-kHalfFov, kHalfFov}) {
      l.move_to(cr, eye);
      l.line_to(cr, along(eye, h + edge, reach));
      cairo_stroke(cr);
    }
    const double dots[] = {1.5 * l.u, 4 * l.u};
    cairo_set_dash(cr, dots, 2, 0);
    set(cr, kEyeColour[side], 0.3);
    l.move_to(cr, eye);
    l.line_to(cr, along(eye, h, reach));
    cairo_stroke(cr);
    cairo_set_dash(cr, nullptr, 0, 0);
  }
  cairo_restore(cr);
}

// Each eye's line of sight to the stimulus, over the objects: solid to the stereo fix when there is
// one, else dashed along the bearing the eye reports (a single eye's sighting has no range).
void draw_sight_lines(cairo_t* cr, const Layout& l, const Frame& frame) {
  const double reach = std::hypot(l.xmax - l.xmin, l.ymax - l.ymin);
  cairo_save(cr);
  cairo_rectangle(cr, l.x0, l.y0, l.aw, l.ah);
  cairo_clip(cr);
  cairo_set_line_width(cr, 1.5 * l.u);
  for (int side = 0; side < 2; ++side) {
    const Vec2& eye = frame.eyes[side];
    const double h = frame.eye_heading[side];
    if (!finite(eye) || !std::isfinite(h)) continue;
    const Sighting& s = frame.senses.stimulus[side];
    if (frame.senses.stereo_valid && finite(frame.senses.stimulus_world)) {
      // Stop at the cross-hair's gap so the line does not hide what is under the fix.
      const Vec2 to = frame.senses.stimulus_world - eye;
      const double gap = kFixGap * l.u / l.scale;
      if (to.norm() > gap) {
        set(cr, kEyeColour[side], 0.9);
        l.move_to(cr, eye);
        l.line_to(cr, frame.senses.stimulus_world - to.normalized() * gap);
        cairo_stroke(cr);
      }
    } else if (s.seen && std::isfinite(s.bearing)) {
      const double dash[] = {7 * l.u, 4 * l.u};
      cairo_set_dash(cr, dash, 2, 0);
      set(cr, kEyeColour[side], 0.8);
      l.move_to(cr, eye);
      l.line_to(cr, along(eye, h + s.bearing, reach));
      cairo_stroke(cr);
      cairo_set_dash(cr, nullptr, 0, 0);
    }
  }
  cairo_restore(cr);
}

// ---- Roger
// ---------------------------------------------------------------------------------------

// Roger: wheels, base with a heading mark, arms, hands marked L and R, and the eyes.
void draw_robot(cairo_t* cr, const Layout& l, const Frame& frame, const RobotParams& rp) {
  const Pose& base = frame.base;
  if (!finite(base)) return;
  cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);

  // Wheels stick out of the base (axle half-width 0.20 m > radius 0.16 m): they show which way
  // Roger can roll and that he cannot slide sideways.
  const double wl = 0.07, ww = 0.025;
  for (double side : {-1.0, 1.0}) {
    const double y = side * rp.axle_half_width;
    cairo_new_path(cr);
    l.move_to(cr, to_world(base, Vec2(-wl, y - ww)));
    l.line_to(cr, to_world(base, Vec2(wl, y - ww)));
    l.line_to(cr, to_world(base, Vec2(wl, y + ww)));
    l.line_to(cr, to_world(base, Vec2(-wl, y + ww)));
    cairo_close_path(cr);
    set(cr, kWheel);
    cairo_fill(cr);
  }

  // Base disk with a forward-pointing triangle for the heading.
  cairo_new_path(cr);
  disk_path(cr, l, Vec2(base.x, base.y), rp.base_radius);
  set(cr, kRobotBody);
  cairo_fill_preserve(cr);
  set(cr, kRobotOutline);
  cairo_set_line_width(cr, 2.0 * l.u);
  cairo_stroke(cr);
  const double r = rp.base_radius;
  cairo_new_path(cr);
  l.move_to(cr, to_world(base, Vec2(0.85 * r, 0)));
  l.line_to(cr, to_world(base, Vec2(0.2 * r, 0.3 * r)));
  l.line_to(cr, to_world(base, Vec2(0.2 * r, -0.3 * r)));
  cairo_close_path(cr);
  set(cr, kRobotOutline, 0.75);
  cairo_fill(cr);

  // Arms: links as thick round-capped strokes, joints as small rings, hands as disks.
  const double link_px = std::max(rp.link_width * l.scale, 3.0 * l.u);
  for (int side = 0; side < 2; ++side) {
    const ArmPoints& a = frame.arms[side];
    if (!finite(a.shoulder) || !finite(a.elbow) || !finite(a.hand)) continue;
    cairo_new_path(cr);
    l.move_to(cr, a.shoulder);
    l.line_to(cr, a.elbow);
    l.line_to(cr, a.hand);
    set(cr, kArm);
    cairo_set_line_width(cr, link_px);
    cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
    cairo_stroke(cr);
    for (const Vec2* j : {&a.shoulder, &a.elbow}) {
      cairo_new_path(cr);
      cairo_arc(cr, l.px(j->x()), l.py(j->y()), 0.3 * link_px, 0, 2 * kPi);
      set(cr, kWhite);
      cairo_fill(cr);
    }
    cairo_new_path(cr);
    disk_path(cr, l, a.hand, rp.hand_radius);
    set(cr, kRobotBody);
    cairo_fill_preserve(cr);
    set(cr, kRobotOutline);
    cairo_set_line_width(cr, 2.0 * l.u);
    cairo_stroke(cr);
    // L and R on the hands: which arm is which is the first thing one asks.
    TextStyle st;
    st.size = std::min(12.0, 0.9 * rp.hand_radius * l.scale / l.u);
    st.bold = true;
    st.colour = kRobotOutline;
    st.align = 0.5;
    text(cr, l, side == kLeft ? "L" : "R", l.px(a.hand.x()),
         l.py(a.hand.y()) + 0.36 * st.size * l.u, st);
  }

  // Eyes: dots in their own colours, with a short line along the optical axis.
  for (int side = 0; side < 2; ++side) {
    const Vec2& e = frame.eyes[side];
    if (!finite(e) || !std::isfinite(frame.eye_heading[side])) continue;
    cairo_new_path(cr);
    l.move_to(cr, e);
    l.line_to(cr, along(e, frame.eye_heading[side], 0.055));
    set(cr, kEyeColour[side]);
    cairo_set_line_width(cr, 2.0 * l.u);
    cairo_stroke(cr);
    cairo_new_path(cr);
    cairo_arc(cr, l.px(e.x()), l.py(e.y()), std::max(0.022 * l.scale, 3.0 * l.u), 0, 2 * kPi);
    set(cr, kEyeColour[side]);
    cairo_fill_preserve(cr);
    set(cr, kWhite);
    cairo_set_line_width(cr, 1.2 * l.u);
    cairo_stroke(cr);
  }
}

// Contact forces: an arrow along the normal (the way the touched surface pushes the sensor) whose
// tip is the contact point, so it lies over the thing touched and leaves Roger visible. Its length
// is proportional to the force, capped; its tail carries the force in newtons.
void draw_contacts(cairo_t* cr, const Layout& l, const Senses& senses, const RenderOptions& o) {
  for (int t = 0; t < kTactileCount; ++t) {
    const Touch& touch = senses.touch[t];
    if (!touch.contact || !finite(touch.point)) continue;
    const double x = l.px(touch.point.x()), y = l.py(touch.point.y());
    const double n = touch.normal.norm();
    if (std::isfinite(n) && n > 1e-9 && std::isfinite(touch.force) && touch.force > 0) {
      const double len_m = std::min(touch.force * o.arrow_metres_per_newton, o.arrow_max_metres);
      const double len = std::max(len_m * l.scale, 10 * l.u);
      const double dx = touch.normal.x() / n, dy = -touch.normal.y() / n;  // device y is down
      const double bx = x - dx * len, by = y - dy * len;                   // the tail
      const double head = std::min(9 * l.u, 0.5 * len), half = 0.5 * head;
      for (int pass = 0; pass < 2; ++pass) {
        set(cr, pass == 0 ? kWhite : kContact, pass == 0 ? 0.8 : 1.0);
        cairo_set_line_width(cr, (pass == 0 ? 5.0 : 2.5) * l.u);
        cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
        cairo_move_to(cr, bx, by);
        cairo_line_to(cr, x - dx * head * 0.8, y - dy * head * 0.8);
        cairo_stroke(cr);
        cairo_move_to(cr, x, y);
        cairo_line_to(cr, x - dx * head - dy * half, y - dy * head + dx * half);
        cairo_line_to(cr, x - dx * head + dy * half, y - dy * head - dx * half);
        cairo_close_path(cr);
        if (pass == 0) {
          cairo_stroke(cr);
        } else {
          cairo_fill(cr);
        }
      }
      TextStyle st;
      st.size = 10;
      st.colour = kContact;
      st.bold = true;
      st.halo = true;
      // Beside the shaft's middle, on its upper side: the tail may sit on whatever is at the centre
      // of a small object (such as the stereo fix).
      double nx = -dy, ny = dx;
      if (ny > 0) nx = -nx, ny = -ny;
      const double mx = 0.5 * (x + bx) + nx * 7 * l.u, my = 0.5 * (y + by) + ny * 7 * l.u;
      st.align = std::fabs(nx) < 0.3 ? 0.5 : (nx > 0 ? 0.0 : 1.0);
      text(cr, l, format("%.1f N", touch.force), mx, my + (ny > -0.3 ? 4 : 0) * l.u, st);
      continue;
    }
    // A contact without a usable force or normal is still a contact: a dot marks where.
    cairo_new_path(cr);
    cairo_arc(cr, x, y, 3 * l.u, 0, 2 * kPi);
    set(cr, kContact);
    cairo_fill_preserve(cr);
    set(cr, kWhite);
    cairo_set_line_width(cr, 1.0 * l.u);
    cairo_stroke(cr);
  }
}

// ---- images
// --------------------------------------------------------------------------------------

// An eye-frame angle in words: "12.3° left".
std::string bearing_text(double angle) {
  const double deg = angle * 180.0 / kPi;
  if (std::fabs(deg) < 0.05) return "straight ahead";
  return format("%.1f\u00b0 ", std::fabs(deg)) + (deg > 0 ? "left" : "right");
}

// One eye's image as a strip of 128 cells. Pixel 127 looks 45 degrees left, so it is drawn at the
// left end: the strip reads like the view from behind the eye. The detected stimulus is bracketed.
void draw_eye_strip(cairo_t* cr, const Layout& l, const Senses& senses, int side, double top) {
  const double sx = l.block_x, sw = l.block_w;
  const double cw = sw / kPixels;
  const double label_base = top + 14 * l.u;
  const double st_top = top + 22 * l.u, st_h = 24 * l.u;
  auto x_of = [&](double u) { return sx + (kPixels - 0.5 - u) * cw; };

  TextStyle name;
  name.size = 12;
  name.bold = true;
  name.colour = kEyeColour[side];
  text(cr, l, kEyeName[side], sx, label_base, name);
  const Sighting& s = senses.stimulus[side];
  TextStyle info;
  info.size = 11;
  info.colour = kFaintInk;
  info.align = 1.0;
  const std::string seen =
      s.seen ? format("stimulus at pixel %.1f (extent %.1f\u2013%.1f), ", s.u, s.u_lo, s.u_hi) +
                   bearing_text(s.bearing)
             : std::string("stimulus not seen");
  text(cr, l, seen, sx + sw, label_base, info);

  // Cell edges are rounded to whole device pixels and shared by neighbours, so there are neither
  // anti-aliased seams between cells nor gaps.
  const EyeImage& img = senses.image[side];
  cairo_save(cr);
  cairo_set_antialias(cr, CAIRO_ANTIALIAS_NONE);
  for (int i = kPixels - 1; i >= 0; --i) {
    const double x0 = std::round(x_of(i + 0.5)), x1 = std::round(x_of(i - 0.5));
    cairo_rectangle(cr, x0, std::round(st_top), x1 - x0,
                    std::round(st_top + st_h) - std::round(st_top));
    set(cr, rgb(img.colour[i]));
    cairo_fill(cr);
  }
  cairo_restore(cr);
  cairo_rectangle(cr, sx, st_top, sw, st_h);
  set(cr, kInk);
  cairo_set_line_width(cr, 1.0 * l.u);
  cairo_stroke(cr);

  // Angle ticks under the strip every 16 pixels, labelled at both ends and the centre.
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
  tick.align = 0.0;
  text(cr, l, "45\u00b0 left (pixel 127)", sx, tick_base, tick);
  tick.align = 0.5;
  text(cr, l, "ahead", sx + 0.5 * sw, tick_base, tick);
  tick.align = 1.0;
  text(cr, l, "(pixel 0) 45\u00b0 right", sx + sw, tick_base, tick);

  if (s.seen && std::isfinite(s.u_lo) && std::isfinite(s.u_hi) && std::isfinite(s.u)) {
    const double xa = x_of(std::max(s.u_hi, s.u_lo)), xb = x_of(std::min(s.u_hi, s.u_lo));
    const double pad = 3 * l.u;
    for (int pass = 0; pass < 2; ++pass) {
      set(cr, pass == 0 ? kWhite : kInk);
      cairo_set_line_width(cr, (pass == 0 ? 4.0 : 1.8) * l.u);
      cairo_rectangle(cr, xa, st_top - pad, std::max(xb - xa, 1.0 * l.u), st_h + 2 * pad);
      cairo_stroke(cr);
    }
    // A notch above the centre, where the bearing is taken.
    const double xc = x_of(s.u);
    cairo_move_to(cr, xc, st_top - pad);
    cairo_line_to(cr, xc - 4 * l.u, st_top - pad - 6 * l.u);
    cairo_line_to(cr, xc + 4 * l.u, st_top - pad - 6 * l.u);
    cairo_close_path(cr);
    set(cr, kInk);
    cairo_fill(cr);
  }
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

// Title, scenario and seed on the left, the time on the right.
void draw_header(cairo_t* cr, const Layout& l, const WorldSpec& spec, const Frame& frame,
                 const RenderOptions& o, double width) {
  const double y = 26 * l.u;
  TextStyle st;
  st.size = 16;
  st.bold = true;
  double x = kLeftBand * l.u;
  if (!o.title.empty()) x += text(cr, l, o.title, x, y, st) + 12 * l.u;
  if (!spec.scenario.empty()) {
    TextStyle sub;
    sub.size = 12;
    sub.colour = kFaintInk;
    text(cr, l, "scenario " + spec.scenario + ", seed " + std::to_string(spec.seed), x, y, sub);
  }
  st.align = 1.0;
  st.bold = false;
  text(cr, l, format("t = %.2f s", frame.time), width - kRightBand * l.u, y, st);
}

// ---- files
// ---------------------------------------------------------------------------------------

enum class Format { kPng, kSvg };

// The file format named by path's extension, or an Error naming the two accepted ones.
Format format_of(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::string lower = ext;
  for (char& c : lower) c = char(std::tolower(static_cast<unsigned char>(c)));
  if (lower == ".png") return Format::kPng;
  if (lower == ".svg") return Format::kSvg;
  throw Error(
      "render: cannot write picture '" + path + "': " +
      (ext.empty() ? std::string("it has no extension") : "unknown extension '" + ext + "'") +
      "; use .png or .svg");
}

// Owns a cairo surface and context for the length of one drawing.
struct Canvas {
  cairo_surface_t* surface = nullptr;
  cairo_t* cr = nullptr;
  ~Canvas() {
    if (cr) cairo_destroy(cr);
    if (surface) cairo_surface_destroy(surface);
  }
};

constexpr int kMaxPicturePixels = 32767;  // cairo's image surface limit per side

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
  if (options.show_fields_of_view) draw_fields_of_view(cr, l, frame);
  draw_things(cr, l, spec, poses);
  if (options.show_fields_of_view) draw_sight_lines(cr, l, frame);
  draw_robot(cr, l, frame, options.robot);
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
