// robot_picture.cpp: Roger on the floor (wheels, base, arms, hands, eyes), what his eyes see
// (fields of view, sight lines, the stereo fix) and what he touches (contact forces).
#include "view/render_internal.h"

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "core/shape.h"

namespace roger::picture {
namespace {

// ---- eyes
// ----------------------------------------------------------------------------------------

// The stereo fix's cross-hair: the gap left open at its centre and the length of its arms.
constexpr double kFixGap = 6;  // design units
constexpr double kFixArm = 15;

// The point length metres from `from` in the world direction angle.
Vec2 along(const Vec2& from, double angle, double length) {
  return from + length * Vec2(std::cos(angle), std::sin(angle));
}

}  // namespace

// The stereo fix: a haloed cross-hair with an open centre, so the object under it stays visible and
// the gap between the estimate and the true centre can be judged.
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

// Each eye's +-45 degree wedge on the floor (clipped to the arena) and its dotted optical axis.
void draw_fields_of_view(cairo_t* cr, const Layout& l, const Frame& frame, double half_fov) {
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
      l.line_to(cr, along(eye, h - half_fov + 2 * half_fov * i / kArcSteps, reach));
    cairo_close_path(cr);
    set(cr, kEyeColour[side], 0.05);
    cairo_fill(cr);
    cairo_set_line_width(cr, 1.0 * l.u);
    set(cr, kEyeColour[side], 0.35);
    for (double edge : {-half_fov, half_fov}) {
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

namespace {

// Wheels stick out of the base (axle half-width 0.20 m > radius 0.16 m): they show which way
// Roger can roll and that he cannot slide sideways.
void draw_wheels(cairo_t* cr, const Layout& l, const Pose& base, const RobotParams& rp) {
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
}

// Base disk with a forward-pointing triangle for the heading.
void draw_base(cairo_t* cr, const Layout& l, const Pose& base, const RobotParams& rp) {
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
}

// Arms: links as thick round-capped strokes, joints as small rings, hands as disks.
void draw_arms(cairo_t* cr, const Layout& l, const Frame& frame, const RobotParams& rp) {
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
}

// Eyes: dots in their own colours, with a short line along the optical axis.
void draw_eyes(cairo_t* cr, const Layout& l, const Frame& frame) {
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

}  // namespace

// Roger: wheels, base with a heading mark, arms, hands marked L and R, and the eyes.
void draw_robot(cairo_t* cr, const Layout& l, const Frame& frame, const RobotParams& rp) {
  const Pose& base = frame.base;
  if (!finite(base)) return;
  cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
  draw_wheels(cr, l, base, rp);
  draw_base(cr, l, base, rp);
  draw_arms(cr, l, frame, rp);
  draw_eyes(cr, l, frame);
}

namespace {

// One force arrow: its tip at (x, y), its tail `len` back along the unit direction (dx, dy).
void draw_force_arrow(cairo_t* cr, const Layout& l, double x, double y, double dx, double dy, double len) {
  const double bx = x - dx * len, by = y - dy * len;  // the tail
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
}

}  // namespace

// Contact forces: an arrow along the normal (the way the touched surface pushes the sensor) whose
// tip is the contact point, so it lies over the thing touched and leaves Roger visible. Its length
// is proportional to the force, capped; its tail carries the force in newtons.
void draw_contacts(cairo_t* cr, const Layout& l, const Senses& senses, const RenderOptions& o) {
  TextStyle st;
  st.size = 10;
  st.colour = kContact;
  st.bold = true;
  st.halo = true;
  std::vector<std::string> labels;  // drawn after every arrow, moved apart where they meet
  std::vector<LabelBox> boxes;
  for (int t = 0; t < kTactileCount; ++t) {
    const Touch& touch = senses.touch[t];
    if (!touch.contact || !finite(touch.point)) continue;
    const double x = l.px(touch.point.x()), y = l.py(touch.point.y());
    const double n = touch.normal.norm();
    if (std::isfinite(n) && n > 1e-9 && std::isfinite(touch.force) && touch.force > 0) {
      const double len_m = std::min(touch.force * o.arrow_metres_per_newton, o.arrow_max_metres);
      const double len = std::max(len_m * l.scale, 10 * l.u);
      const double dx = touch.normal.x() / n, dy = -touch.normal.y() / n;  // device y is down
      draw_force_arrow(cr, l, x, y, dx, dy, len);
      // Beside the shaft's middle, on its upper side: the tail may sit on whatever is at the centre
      // of a small object (such as the stereo fix).
      double nx = -dy, ny = dx;
      if (ny > 0) nx = -nx, ny = -ny;
      const double mx = x - 0.5 * dx * len + nx * 7 * l.u, my = y - 0.5 * dy * len + ny * 7 * l.u;
      const double align = std::fabs(nx) < 0.3 ? 0.5 : (nx > 0 ? 0.0 : 1.0);
      const std::string label = format("%.1f N", touch.force);
      const double w = text_width(cr, l, label, st), base = my + (ny > -0.3 ? 4 : 0) * l.u;
      labels.push_back(label);
      boxes.push_back({mx - align * w, base - st.size * l.u, mx + (1 - align) * w, base + 0.25 * st.size * l.u});
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
  separate_labels(boxes);
  st.align = 0.0;  // each box's left edge
  for (size_t k = 0; k < labels.size(); ++k)
    text(cr, l, labels[k], boxes[k].x0, boxes[k].y1 - 0.25 * st.size * l.u, st);
}

}  // namespace roger::picture
