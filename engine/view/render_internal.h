// render_internal.h: what the files drawing a world picture share (private to view/): the
// furniture's sizes, the palette, the layout mapping metres to pixels, the text helper, and the
// parts of the picture. render.cpp lays out and writes pictures, world_picture.cpp draws the
// arena and what stands in it, robot_picture.cpp draws Roger, his eyes' views and his contacts,
// eye_strips.cpp the images and the status line under the arena.
#pragma once

#include <cairo.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "core/robot.h"
#include "core/spec.h"
#include "senses/senses.h"
#include "sim/world.h"
#include "view/ink.h"
#include "view/render.h"

namespace roger::picture {

constexpr double kPi = 3.14159265358979323846;

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
inline const Rgb kBackground = rgb(255, 255, 255);
inline const Rgb kFloor = rgb(248, 247, 242);
inline const Rgb kRobotBody = rgb(214, 222, 234);
inline const Rgb kRobotOutline = rgb(38, 44, 56);
inline const Rgb kArm = rgb(66, 74, 90);
inline const Rgb kWheel = rgb(45, 45, 50);
inline const Rgb kEyeColour[2] = {rgb(30, 100, 220), rgb(232, 118, 18)};
inline const Rgb kContact = rgb(205, 0, 145);

// Whether a point or a pose can be drawn.
inline bool finite(const Vec2& p) { return std::isfinite(p.x()) && std::isfinite(p.y()); }
inline bool finite(const Pose& p) {
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
double text_width(cairo_t* cr, const Layout& l, const std::string& s, const TextStyle& st);

// Draws text with its baseline at y; returns the width drawn.
double text(cairo_t* cr, const Layout& l, const std::string& s, double x, double y,
            const TextStyle& st);

// A label's box in device pixels (y down: y0 its top, y1 its bottom).
struct LabelBox {
  double x0, y0, x1, y1;
};

// Moves each box down, by whole heights of its own, until it overlaps none before it (at most
// `tries` moves; the first box stays). The force labels of three contacts around a small object
// sat on each other ("53.13 N 43.5" read as one number).
void separate_labels(std::vector<LabelBox>& boxes, int tries = 6);

// ---- the parts of a picture, in the order draw_frame draws them
// ----------------------------------------------------------------------------------------

// Adds a world disk to the current path as its own closed sub-path (world_picture.cpp).
void disk_path(cairo_t* cr, const Layout& l, const Vec2& c, double r);

// Walls, floor, the origin axes (or the whole grid) and the metric scale on two sides.
void draw_arena(cairo_t* cr, const Layout& l, const WorldSpec& spec, const RenderOptions& o);

// Goal regions: translucent disks with a dashed rim, drawn first because they are floor markings.
void draw_goals(cairo_t* cr, const Layout& l, const WorldSpec& spec);

// Object poses for this frame: the frame's, or the spec's starting poses for a frame without any
// (a scenario preview before the first tick).
std::vector<Pose> object_poses(const WorldSpec& spec, const Frame& frame);

// Obstacles, then objects over them, each part in its own colour.
void draw_things(cairo_t* cr, const Layout& l, const WorldSpec& spec,
                 const std::vector<Pose>& poses);

// Names of goals, obstacles and objects, last so that nothing covers them.
void draw_labels(cairo_t* cr, const Layout& l, const WorldSpec& spec,
                 const std::vector<Pose>& poses);

// Each eye's +-45 degree wedge on the floor (clipped to the arena) and its dotted optical axis
// (robot_picture.cpp, as the three below).
void draw_fields_of_view(cairo_t* cr, const Layout& l, const Frame& frame, double half_fov);

// Each eye's line of sight to the stimulus, over the objects.
void draw_sight_lines(cairo_t* cr, const Layout& l, const Frame& frame);

// Roger: wheels, base with a heading mark, arms, hands marked L and R, and the eyes.
void draw_robot(cairo_t* cr, const Layout& l, const Frame& frame, const RobotParams& rp);

// The stereo fix: a haloed cross-hair with an open centre.
void draw_stereo_fix(cairo_t* cr, const Layout& l, const Senses& senses);

// Contact forces as arrows whose tips are the contact points.
void draw_contacts(cairo_t* cr, const Layout& l, const Senses& senses, const RenderOptions& o);

// One eye's image as a strip of 128 cells, its top at `top` (eye_strips.cpp, as the one below).
void draw_eye_strip(cairo_t* cr, const Layout& l, const Senses& senses, int side, double top);

// One line under everything: the stereo fix and the three touch sensors, in numbers.
void draw_status(cairo_t* cr, const Layout& l, const Senses& senses);

}  // namespace roger::picture
