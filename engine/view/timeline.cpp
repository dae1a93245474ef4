// timeline.cpp: the controller-state timeline under an episode's frames and summary: computed once
// from the episode (make_timeline), then drawn part by part (heading, legend, rows of runs, time
// axis, cursors).
#include "view/animation_internal.h"

#include <algorithm>
#include <cmath>

namespace roger::anim {
namespace {

constexpr double kPi = 3.14159265358979323846;

// How a label is drawn.
struct TextStyle {
  double size = 12;  // design units
  Rgb colour = kInk;
  bool bold = false;
  double align = 0.0;  // 0 left, 0.5 centre, 1 right of x
};

// Makes the style's face and size cr's font.
void select_font(cairo_t* cr, double u, const TextStyle& st) {
  cairo_select_font_face(cr, "DejaVu Sans", CAIRO_FONT_SLANT_NORMAL,
                         st.bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, st.size * u);
}

// Width of a text in device pixels.
double text_width(cairo_t* cr, double u, const std::string& s, const TextStyle& st) {
  select_font(cr, u, st);
  cairo_text_extents_t e;
  cairo_text_extents(cr, s.c_str(), &e);
  return e.x_advance;
}

// Draws text with its baseline at y; returns the width drawn.
double text(cairo_t* cr, double u, const std::string& s, double x, double y, const TextStyle& st) {
  const double w = text_width(cr, u, s, st);
  cairo_move_to(cr, x - st.align * w, y);
  set(cr, st.colour);
  cairo_show_text(cr, s.c_str());
  return w;
}

// s shortened with an ellipsis to fit max_w, cutting only between UTF-8 characters.
std::string elide(cairo_t* cr, double u, std::string s, double max_w, const TextStyle& st) {
  if (text_width(cr, u, s, st) <= max_w) return s;
  while (!s.empty()) {
    // Drop the last whole character: its continuation bytes, then its first byte.
    while (!s.empty() && (static_cast<unsigned char>(s.back()) & 0xC0) == 0x80) s.pop_back();
    if (!s.empty()) s.pop_back();
    if (text_width(cr, u, s + "\u2026", st) <= max_w) return s + "\u2026";
  }
  return "\u2026";
}

// The timeline's furniture in design units (one unit is a pixel of a 1000-pixel-wide panel).
constexpr double kTlTop = 10;       // rule and breathing room above the heading
constexpr double kTlHeading = 28;   // "controller states", outcome, legend; room for the cursor's tip
constexpr double kTlMarkers = 22;   // numbered panel markers (summary only)
constexpr double kTlRow = 24;       // one controller
constexpr double kTlBar = 16;       // its bar
constexpr double kTlAxis = 30;      // time ticks and labels
constexpr double kTlBottom = 8;
constexpr double kTlLeft = 60;      // as render.cpp's left band: names line up with the text above
constexpr double kTlRight = 26;     // as render.cpp's right band
constexpr double kTlStateColumn = 70;  // the current state, right of the bars (frames only)

}  // namespace

std::string outcome_text(const Timeline& tl) {
  return std::string(tl.success ? "success" : "timeout") + format(" after %.2f s", tl.sim_seconds) +
         ", reward " + number_text(tl.reward);
}

Timeline make_timeline(const EpisodeResult& ep) {
  Timeline tl;
  // The control period is not stored in the result; the episode's own clock gives it exactly.
  if (ep.ticks > 0 && ep.sim_seconds > 0) {
    tl.dt = ep.sim_seconds / ep.ticks;
  } else {
    for (size_t i = 0; i < ep.frames.size() && i < ep.frame_ticks.size(); ++i)
      if (ep.frame_ticks[i] > 0 && ep.frames[i].time > 0) {
        tl.dt = ep.frames[i].time / ep.frame_ticks[i];
        break;
      }
  }
  tl.success = ep.success;
  tl.reward = ep.reward;
  tl.sim_seconds = ep.sim_seconds;
  double end = std::max(ep.sim_seconds, ep.ticks * tl.dt);
  for (const Frame& f : ep.frames)
    if (std::isfinite(f.time)) end = std::max(end, f.time);
  for (const GammaTrace& g : ep.gammas) end = std::max(end, double(g.states.size()) * tl.dt);
  tl.t_end = end > 0 ? end : 1.0;

  for (const GammaTrace& g : ep.gammas) {
    Row row;
    row.name = valid_utf8(g.name.empty() ? std::string("(unnamed)") : g.name);
    row.states = &g.states;
    // State i was evaluated at the end of tick i, so it covers [i dt, (i+1) dt]: everything left of
    // a frame's cursor is what the controller had reported by then.
    for (size_t i = 0; i < g.states.size(); ++i) {
      const double t0 = double(i) * tl.dt, t1 = double(i + 1) * tl.dt;
      if (!row.runs.empty() && row.runs.back().gamma == g.states[i])
        row.runs.back().t1 = t1;
      else
        row.runs.push_back({t0, t1, g.states[i]});
    }
    tl.rows.push_back(std::move(row));
  }

  const bool have_ticks = ep.frame_ticks.size() == ep.frames.size();
  for (size_t i = 0; i < ep.frames.size(); ++i) {
    const double t = ep.frames[i].time;
    tl.frame_ticks.push_back(have_ticks      ? std::lround(ep.frame_ticks[i])
                             : std::isfinite(t) ? std::lround(t / tl.dt)
                                                : 0);
  }
  return tl;
}

double timeline_height(const Timeline& tl, TimelineMode mode, double u) {
  const double rows = double(std::max<size_t>(tl.rows.size(), 1));
  return (kTlTop + kTlHeading + (mode == TimelineMode::kSummary ? kTlMarkers : 0) + rows * kTlRow +
          kTlAxis + kTlBottom) *
         u;
}

void number_badge(cairo_t* cr, double u, double x, double y, int n) {
  const double r = 9.5 * u;
  cairo_new_path(cr);
  cairo_arc(cr, x, y, r, 0, 2 * kPi);
  set(cr, kInk);
  cairo_fill(cr);
  TextStyle st;
  st.size = 11;
  st.bold = true;
  st.colour = kWhite;
  st.align = 0.5;
  text(cr, u, std::to_string(n), x, y + 4 * u, st);
}

namespace {

// Where the timeline's columns and rows fall in device pixels, shared by its parts.
struct TimelineLayout {
  double name_w = 0;                 // the names' column, right of kTlLeft
  double bx0 = 0, bx1 = 0, bw = 0;   // the bars' left and right ends and their width
  double t_end = 1;                  // the time at the bars' right end
  double rows_top = 0, rows_bottom = 0;
  double bar_pad = 0;                // from a row's top to its bar's

  // The x of time t, clamped to the bars.
  double xt(double t) const { return bx0 + bw * std::clamp(t / t_end, 0.0, 1.0); }
};

// The style of the controllers' names, for measuring them and for drawing them.
TextStyle name_style() {
  TextStyle st;
  st.size = 12;
  return st;
}

// A faint rule separates the timeline from the picture above it.
void draw_rule(cairo_t* cr, double x, double y, double width, double u) {
  set(cr, kRule);
  cairo_set_line_width(cr, 1.0 * u);
  cairo_move_to(cr, x + kTlLeft * u, y + 0.5 * u);
  cairo_line_to(cr, x + width - kTlRight * u, y + 0.5 * u);
  cairo_stroke(cr);
}

// Heading: what this is and how the episode ended, on the left.
void draw_heading(cairo_t* cr, const Timeline& tl, double x, double head_base, double u) {
  TextStyle head;
  head.size = 13;
  head.bold = true;
  double hx = x + kTlLeft * u;
  hx += text(cr, u, "controller states", hx, head_base, head) + 14 * u;
  TextStyle outcome;
  outcome.size = 12;
  outcome.bold = true;
  outcome.colour = tl.success ? kSuccess : kFailure;
  text(cr, u, outcome_text(tl), hx, head_base, outcome);
}

// The legend on the right of the heading: each state's colour, name and meaning.
void draw_legend(cairo_t* cr, double x, double width, double head_base, double u) {
  TextStyle legend;
  legend.size = 11;
  legend.colour = kInk;
  double lx = x + width - kTlRight * u;
  for (int g = 2; g >= 0; --g) {
    TextStyle meaning = legend;
    meaning.colour = kFaintInk;
    lx -= text_width(cr, u, kGammaMeaning[g], meaning);
    text(cr, u, kGammaMeaning[g], lx, head_base, meaning);
    lx -= 5 * u;
    TextStyle name = legend;
    name.bold = true;
    const std::string label = gamma_name(Gamma(g));
    lx -= text_width(cr, u, label, name);
    text(cr, u, label, lx, head_base, name);
    lx -= 17 * u;
    cairo_rectangle(cr, lx, head_base - 10 * u, 12 * u, 12 * u);
    set(cr, kGammaColour[g]);
    cairo_fill(cr);
    lx -= 16 * u;
  }
}

// Columns: names, bars, and (for a frame) the state at the cursor; rows under the heading.
TimelineLayout layout_timeline(cairo_t* cr, const Timeline& tl, bool frame_mode, double x,
                               double y, double width, double u) {
  TimelineLayout lay;
  double name_w = 40 * u;
  for (const Row& r : tl.rows) name_w = std::max(name_w, text_width(cr, u, r.name, name_style()));
  lay.name_w = std::min(name_w, 240 * u);
  lay.bx0 = x + kTlLeft * u + lay.name_w + 12 * u;
  lay.bx1 = x + width - kTlRight * u - (frame_mode ? kTlStateColumn * u : 0);
  lay.bw = std::max(lay.bx1 - lay.bx0, 1.0);
  lay.t_end = tl.t_end;

  lay.rows_top = y + (kTlTop + kTlHeading + (frame_mode ? 0 : kTlMarkers)) * u;
  const size_t nrows = std::max<size_t>(tl.rows.size(), 1);
  lay.rows_bottom = lay.rows_top + double(nrows) * kTlRow * u;
  lay.bar_pad = 0.5 * (kTlRow - kTlBar) * u;
  return lay;
}

// An empty track saying that no controller was watched.
void draw_no_rows(cairo_t* cr, const TimelineLayout& lay, double u) {
  cairo_rectangle(cr, lay.bx0, lay.rows_top + lay.bar_pad, lay.bw, kTlBar * u);
  set(cr, kTrack);
  cairo_fill(cr);
  TextStyle none;
  none.size = 11;
  none.colour = kFaintInk;
  none.align = 0.5;
  text(cr, u, "no controllers were watched in this episode", lay.bx0 + 0.5 * lay.bw,
       lay.rows_top + lay.bar_pad + 12 * u, none);
}

// Row r: the controller's name, its track, and its runs coloured by state.
void draw_row(cairo_t* cr, const Row& row, size_t r, const TimelineLayout& lay, double x,
              double u) {
  const double top = lay.rows_top + double(r) * kTlRow * u + lay.bar_pad;
  text(cr, u, elide(cr, u, row.name, lay.name_w, name_style()), x + kTlLeft * u, top + 12.5 * u,
       name_style());
  cairo_rectangle(cr, lay.bx0, top, lay.bw, kTlBar * u);
  set(cr, kTrack);
  cairo_fill(cr);
  // Run edges snap to whole device pixels and are shared by neighbours: no seams, no gaps.
  cairo_save(cr);
  cairo_set_antialias(cr, CAIRO_ANTIALIAS_NONE);
  for (const Run& run : row.runs) {
    const double a = std::round(lay.xt(run.t0)), b = std::round(lay.xt(run.t1));
    cairo_rectangle(cr, a, std::round(top), std::max(b - a, 1.0),
                    std::round(top + kTlBar * u) - std::round(top));
    set(cr, kGammaColour[int(run.gamma) % 3]);
    cairo_fill(cr);
  }
  cairo_restore(cr);
}

// Fading the future keeps the past vivid while the whole episode stays readable.
void fade_future(cairo_t* cr, const TimelineLayout& lay, double time) {
  const double cx = lay.xt(time);
  if (lay.bx1 > cx) {
    cairo_rectangle(cr, cx, lay.rows_top, lay.bx1 - cx, lay.rows_bottom - lay.rows_top);
    set(cr, kWhite, 0.55);
    cairo_fill(cr);
  }
}

// Time axis under the bars: a line, round ticks labelled in seconds, and the unit.
void draw_time_axis(cairo_t* cr, const Timeline& tl, const TimelineLayout& lay, double u) {
  const double axis_y = lay.rows_bottom + 4 * u;
  set(cr, kFaintInk);
  cairo_set_line_width(cr, 1.0 * u);
  cairo_move_to(cr, lay.bx0, axis_y);
  cairo_line_to(cr, lay.bx0 + lay.bw, axis_y);
  cairo_stroke(cr);
  const double step = nice_step(tl.t_end);
  TextStyle tick;
  tick.size = 10;
  tick.colour = kFaintInk;
  tick.align = 0.5;
  const long kmax = std::lround(std::floor(tl.t_end / step + 1e-9));
  for (long k = 0; k <= kmax; ++k) {
    const double tx = lay.xt(k * step);
    set(cr, kFaintInk);
    cairo_move_to(cr, tx, axis_y);
    cairo_line_to(cr, tx, axis_y + 5 * u);
    cairo_stroke(cr);
    text(cr, u, number_text(k * step), tx, axis_y + 17 * u, tick);
  }
  tick.align = 1.0;
  text(cr, u, "time (s)", lay.bx0 - 12 * u, axis_y + 17 * u, tick);
}

// A cursor: a line through every row with a marker above it (a numbered badge in a summary).
void draw_cursor(cairo_t* cr, const Cursor& c, const TimelineLayout& lay, double u) {
  const double cx = lay.xt(c.time);
  const double rows_top = lay.rows_top, rows_bottom = lay.rows_bottom;
  cairo_set_line_width(cr, 2.0 * u);
  set(cr, kWhite, 0.9);
  cairo_move_to(cr, cx, rows_top - 2 * u);
  cairo_line_to(cr, cx, rows_bottom + 2 * u);
  cairo_set_line_width(cr, 4.0 * u);
  cairo_stroke(cr);
  set(cr, kInk);
  cairo_move_to(cr, cx, rows_top - 2 * u);
  cairo_line_to(cr, cx, rows_bottom + 2 * u);
  cairo_set_line_width(cr, 2.0 * u);
  cairo_stroke(cr);
  if (c.label > 0) {
    const double by = rows_top - 12 * u;
    cairo_move_to(cr, cx, by);
    cairo_line_to(cr, cx, rows_top - 2 * u);
    cairo_stroke(cr);
    number_badge(cr, u, cx, by, c.label);
  } else {
    cairo_move_to(cr, cx - 5 * u, rows_top - 7 * u);
    cairo_line_to(cr, cx + 5 * u, rows_top - 7 * u);
    cairo_line_to(cr, cx, rows_top - 1 * u);
    cairo_close_path(cr);
    cairo_fill(cr);
  }
}

// A frame also says in words which state each controller is in at the cursor.
void draw_cursor_states(cairo_t* cr, const Timeline& tl, const TimelineLayout& lay, long tick,
                        double u) {
  TextStyle st;
  st.size = 11;
  st.bold = true;
  for (size_t r = 0; r < tl.rows.size(); ++r) {
    const Gamma* g = tl.state_at(r, tick);
    const double base = lay.rows_top + double(r) * kTlRow * u + lay.bar_pad + 12.5 * u;
    // Darkened, since amber and green text on white read less well than the bars.
    st.colour = g && *g != Gamma::kNoRef ? darker(kGammaColour[int(*g) % 3], 0.8) : kFaintInk;
    text(cr, u, g ? gamma_name(*g) : "\u2013", lay.bx1 + 12 * u, base, st);
  }
}

}  // namespace

TimelineBox draw_timeline(cairo_t* cr, const Timeline& tl, TimelineMode mode,
                          const std::vector<Cursor>& cursors, bool dim_future, double x, double y,
                          double width, double u) {
  cairo_save(cr);
  const bool frame_mode = mode == TimelineMode::kFrame;
  draw_rule(cr, x, y, width, u);
  const double head_base = y + (kTlTop + 16) * u;
  draw_heading(cr, tl, x, head_base, u);
  draw_legend(cr, x, width, head_base, u);

  const TimelineLayout lay = layout_timeline(cr, tl, frame_mode, x, y, width, u);
  if (tl.rows.empty()) draw_no_rows(cr, lay, u);
  for (size_t r = 0; r < tl.rows.size(); ++r) draw_row(cr, tl.rows[r], r, lay, x, u);
  if (frame_mode && dim_future && !cursors.empty() && !tl.rows.empty())
    fade_future(cr, lay, cursors.front().time);
  draw_time_axis(cr, tl, lay, u);
  for (const Cursor& c : cursors) draw_cursor(cr, c, lay, u);
  if (frame_mode && !cursors.empty()) draw_cursor_states(cr, tl, lay, cursors.front().tick, u);
  cairo_restore(cr);
  return {lay.bx0, lay.bx1, lay.rows_top, lay.rows_bottom};
}

}  // namespace roger::anim
