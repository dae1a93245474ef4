// world_picture.cpp: the arena (walls, floor, metric scale) and what stands in it: goal regions,
// obstacles and objects with their names.
#include "view/render_internal.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/error.h"
#include "core/shape.h"

namespace roger::picture {

// ---- shapes
// --------------------------------------------------------------------------------------

// Adds a world disk to the current path as its own closed sub-path. A disk past every corner of
// the drawing's clip is drawn as one just past them (its rim still outside, by more than any line's
// width): the same pixels, where cairo's arc of a goal of radius 1e300 m, in segments by its
// length, never ended (found by a probe).
void disk_path(cairo_t* cr, const Layout& l, const Vec2& c, double r) {
  const double x = l.px(c.x()), y = l.py(c.y());
  double x1 = 0, y1 = 0, x2 = 0, y2 = 0;
  cairo_clip_extents(cr, &x1, &y1, &x2, &y2);
  const double reach = std::hypot(std::max(std::abs(x - x1), std::abs(x2 - x)), std::max(std::abs(y - y1), std::abs(y2 - y)));
  cairo_new_sub_path(cr);
  cairo_arc(cr, x, y, std::min(r * l.scale, reach + 16 * l.u), 0, 2 * kPi);
  cairo_close_path(cr);
}

namespace {

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

// A tick value without trailing zeros or a negative zero.
std::string tick_label(double v) {
  if (std::fabs(v) < 1e-9) v = 0;
  return format("%g", v);
}

// Which metric ticks the arena shows: every step metres, from kx0 * step to kx1 * step along x and
// from ky0 * step to ky1 * step along y.
struct ArenaTicks {
  double step;
  long kx0, kx1, ky0, ky1;
};

// The ticks of a round step that fall inside the arena.
ArenaTicks arena_ticks(const Layout& l) {
  const double step = nice_step(std::max(l.xmax - l.xmin, l.ymax - l.ymin));
  const long kx0 = std::lround(std::ceil(l.xmin / step - 1e-9));
  const long kx1 = std::lround(std::floor(l.xmax / step + 1e-9));
  const long ky0 = std::lround(std::ceil(l.ymin / step - 1e-9));
  const long ky1 = std::lround(std::floor(l.ymax / step + 1e-9));
  return {step, kx0, kx1, ky0, ky1};
}

// Walls: a band around the floor, so the floor itself is exactly the arena.
void draw_walls_and_floor(cairo_t* cr, const Layout& l, const WorldSpec& spec) {
  const double w = kWall * l.u;
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
}

// Floor lines: faint everywhere when asked for, and always a little stronger through the origin
// so the world axes are easy to find.
void draw_floor_lines(cairo_t* cr, const Layout& l, const RenderOptions& o, const ArenaTicks& t) {
  const double step = t.step;
  cairo_set_line_width(cr, 1.0 * l.u);
  for (long k = t.kx0; k <= t.kx1; ++k) {
    const bool axis = k == 0;
    if (!o.show_grid && !axis) continue;
    set(cr, kInk, axis ? 0.14 : 0.07);
    cairo_move_to(cr, l.px(k * step), l.y0);
    cairo_line_to(cr, l.px(k * step), l.y0 + l.ah);
    cairo_stroke(cr);
  }
  for (long k = t.ky0; k <= t.ky1; ++k) {
    const bool axis = k == 0;
    if (!o.show_grid && !axis) continue;
    set(cr, kInk, axis ? 0.14 : 0.07);
    cairo_move_to(cr, l.x0, l.py(k * step));
    cairo_line_to(cr, l.x0 + l.aw, l.py(k * step));
    cairo_stroke(cr);
  }
}

// Ticks and metre labels outside the walls.
void draw_metric_scale(cairo_t* cr, const Layout& l, const ArenaTicks& t) {
  const double w = kWall * l.u;
  const double step = t.step;
  TextStyle st;
  st.size = 11;
  st.colour = kFaintInk;
  set(cr, kFaintInk);
  cairo_set_line_width(cr, 1.0 * l.u);
  const double bottom = l.y0 + l.ah + w;
  for (long k = t.kx0; k <= t.kx1; ++k) {
    const double x = l.px(k * step);
    cairo_move_to(cr, x, bottom);
    cairo_line_to(cr, x, bottom + 5 * l.u);
    cairo_stroke(cr);
    st.align = 0.5;
    text(cr, l, tick_label(k * step), x, bottom + 18 * l.u, st);
  }
  const double left = l.x0 - w;
  for (long k = t.ky0; k <= t.ky1; ++k) {
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

}  // namespace

void draw_arena(cairo_t* cr, const Layout& l, const WorldSpec& spec, const RenderOptions& o) {
  draw_walls_and_floor(cr, l, spec);
  const ArenaTicks t = arena_ticks(l);
  draw_floor_lines(cr, l, o, t);
  draw_metric_scale(cr, l, t);
}

// ---- goals, obstacles, objects
// -------------------------------------------------------------------

// Goal regions: translucent disks with a dashed rim, drawn first because they are floor markings,
// and on the floor only (a goal past a wall tinted the wall, and a large one the whole picture).
void draw_goals(cairo_t* cr, const Layout& l, const WorldSpec& spec) {
  cairo_save(cr);
  cairo_rectangle(cr, l.x0, l.y0, l.aw, l.ah);
  cairo_clip(cr);
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
  cairo_restore(cr);
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

}  // namespace roger::picture
