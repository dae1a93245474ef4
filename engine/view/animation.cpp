#include "view/animation.h"

#include "core/fileio.h"
#include "view/cairo_file.h"
#include "view/ink.h"

#include <cairo.h>
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <random>
#include <sstream>

#include <nlohmann/json.hpp>

#include "episode_page_html.h"  // generated from web/episode.html by embed_text.cmake

#include "control/control.h"
#include "core/error.h"

namespace roger {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

constexpr double kPi = 3.14159265358979323846;

// ---- colours and text
// -----------------------------------------------------------------------------------

using namespace ink;

// Beside the shared ink (ink.h): the timeline's own colours.
const Rgb kRule = rgb(218, 220, 226);
const Rgb kTrack = rgb(241, 242, 245);
const Rgb kSuccess = rgb(30, 130, 70);
const Rgb kFailure = rgb(190, 50, 40);

// State colours, also used by index.html (kept in step with kGammaCss below): grey for "nothing to
// do", amber for "working on it", green for "done", so a glance finds where a controller stalls.
const Rgb kGammaColour[3] = {rgb(178, 182, 190), rgb(240, 166, 0), rgb(44, 160, 84)};
const char* const kGammaCss[3] = {"#b2b6be", "#f0a600", "#2ca054"};
const char* const kGammaMeaning[3] = {"no reference", "descending", "converged"};

// printf-style formatting for labels (std::format is C++20).
template <class... Args>
std::string format(const char* fmt, Args... args) {
  char buf[200];
  std::snprintf(buf, sizeof buf, fmt, args...);
  return buf;
}

// A number without trailing zeros or a negative zero.
std::string number_text(double v) {
  if (std::fabs(v) < 1e-9) v = 0;
  return format("%g", v);
}

// Names come from Lua scripts and may hold any bytes; cairo refuses invalid UTF-8 (and then draws
// nothing more), and the JSON writer would throw, so invalid bytes become '?'.
std::string valid_utf8(const std::string& s) {
  std::string out;
  out.reserve(s.size());
  size_t i = 0;
  while (i < s.size()) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    int len = c < 0x80 ? 1 : (c >> 5) == 0x6 ? 2 : (c >> 4) == 0xE ? 3 : (c >> 3) == 0x1E ? 4 : 0;
    bool ok = len > 0 && i + len <= s.size() && !(len == 2 && c < 0xC2);
    for (int k = 1; ok && k < len; ++k)
      ok = (static_cast<unsigned char>(s[i + k]) & 0xC0) == 0x80;
    if (ok && len == 1 && c < 0x20) ok = false;  // control characters would break a label
    if (ok) {
      out.append(s, i, size_t(len));
      i += size_t(len);
    } else {
      out += '?';
      ++i;
    }
  }
  return out;
}

struct TextStyle {
  double size = 12;  // design units
  Rgb colour = kInk;
  bool bold = false;
  double align = 0.0;  // 0 left, 0.5 centre, 1 right of x
};

void select_font(cairo_t* cr, double u, const TextStyle& st) {
  cairo_select_font_face(cr, "DejaVu Sans", CAIRO_FONT_SLANT_NORMAL,
                         st.bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, st.size * u);
}

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

// A round tick spacing giving at most about ten intervals over span (as render.cpp's metre scale).
double nice_step(double span) {
  const double raw = span / 10.0;
  const double p = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 2.5, 5.0, 10.0})
    if (m * p >= raw - 1e-12) return m * p;
  return 10 * p;
}

// ---- the episode as a timeline
// ----------------------------------------------------------------------------------

// One watched controller's states as runs of equal state, in seconds.
struct Run {
  double t0, t1;
  Gamma gamma;
};

struct Row {
  std::string name;
  std::vector<Run> runs;
  const std::vector<Gamma>* states = nullptr;
};

// What the timeline needs from an episode, computed once for all its frames.
struct Timeline {
  double dt = 0.02;     // seconds per control tick
  double t_end = 1.0;   // right end of the time axis (never 0, so the axis can be scaled)
  bool success = false;
  double reward = 0.0;
  double sim_seconds = 0.0;
  std::vector<Row> rows;
  std::vector<long> frame_ticks;  // the control tick at which each frame was taken

  // The state of row r at a frame taken after `tick` ticks: the state evaluated on the tick that
  // just ran (states[tick - 1]); none before the first tick.
  const Gamma* state_at(size_t r, long tick) const {
    const std::vector<Gamma>& s = *rows[r].states;
    if (tick < 1 || size_t(tick - 1) >= s.size()) return nullptr;
    return &s[size_t(tick - 1)];
  }
};

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

// "success after 3.42 s, reward 100" or "timeout after 5.00 s, reward -100".
std::string outcome_text(const Timeline& tl) {
  return std::string(tl.success ? "success" : "timeout") + format(" after %.2f s", tl.sim_seconds) +
         ", reward " + number_text(tl.reward);
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

enum class TimelineMode { kFrame, kSummary };

double timeline_height(const Timeline& tl, TimelineMode mode, double u) {
  const double rows = double(std::max<size_t>(tl.rows.size(), 1));
  return (kTlTop + kTlHeading + (mode == TimelineMode::kSummary ? kTlMarkers : 0) + rows * kTlRow +
          kTlAxis + kTlBottom) *
         u;
}

// A cursor on the timeline: a time and, in a summary, the panel number it belongs to.
struct Cursor {
  double time;
  int label;  // 0: none
  long tick;
};

// Where the bars go, so the page can map clicks on a frame back to times.
struct TimelineBox {
  double x0 = 0, x1 = 0, y0 = 0, y1 = 0;
};

// A filled circle with a white number: ties a summary panel to its moment on the timeline.
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

// Draws the timeline into the band (x, y)-(x + width, ...) of cr, u device pixels per design unit.
TimelineBox draw_timeline(cairo_t* cr, const Timeline& tl, TimelineMode mode,
                          const std::vector<Cursor>& cursors, bool dim_future, double x, double y,
                          double width, double u) {
  cairo_save(cr);
  const bool frame_mode = mode == TimelineMode::kFrame;

  // A faint rule separates the timeline from the picture above it.
  set(cr, kRule);
  cairo_set_line_width(cr, 1.0 * u);
  cairo_move_to(cr, x + kTlLeft * u, y + 0.5 * u);
  cairo_line_to(cr, x + width - kTlRight * u, y + 0.5 * u);
  cairo_stroke(cr);

  // Heading: what this is and how the episode ended on the left, the legend on the right.
  const double head_base = y + (kTlTop + 16) * u;
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

  // Columns: names, bars, and (for a frame) the state at the cursor.
  TextStyle name_style;
  name_style.size = 12;
  double name_w = 40 * u;
  for (const Row& r : tl.rows) name_w = std::max(name_w, text_width(cr, u, r.name, name_style));
  name_w = std::min(name_w, 240 * u);
  const double bx0 = x + kTlLeft * u + name_w + 12 * u;
  const double bx1 = x + width - kTlRight * u - (frame_mode ? kTlStateColumn * u : 0);
  const double bw = std::max(bx1 - bx0, 1.0);
  auto xt = [&](double t) { return bx0 + bw * std::clamp(t / tl.t_end, 0.0, 1.0); };

  const double rows_top =
      y + (kTlTop + kTlHeading + (frame_mode ? 0 : kTlMarkers)) * u;
  const size_t nrows = std::max<size_t>(tl.rows.size(), 1);
  const double rows_bottom = rows_top + double(nrows) * kTlRow * u;
  const double bar_pad = 0.5 * (kTlRow - kTlBar) * u;

  if (tl.rows.empty()) {
    cairo_rectangle(cr, bx0, rows_top + bar_pad, bw, kTlBar * u);
    set(cr, kTrack);
    cairo_fill(cr);
    TextStyle none;
    none.size = 11;
    none.colour = kFaintInk;
    none.align = 0.5;
    text(cr, u, "no controllers were watched in this episode", bx0 + 0.5 * bw,
         rows_top + bar_pad + 12 * u, none);
  }
  for (size_t r = 0; r < tl.rows.size(); ++r) {
    const Row& row = tl.rows[r];
    const double top = rows_top + double(r) * kTlRow * u + bar_pad;
    text(cr, u, elide(cr, u, row.name, name_w, name_style), x + kTlLeft * u, top + 12.5 * u,
         name_style);
    cairo_rectangle(cr, bx0, top, bw, kTlBar * u);
    set(cr, kTrack);
    cairo_fill(cr);
    // Run edges snap to whole device pixels and are shared by neighbours: no seams, no gaps.
    cairo_save(cr);
    cairo_set_antialias(cr, CAIRO_ANTIALIAS_NONE);
    for (const Run& run : row.runs) {
      const double a = std::round(xt(run.t0)), b = std::round(xt(run.t1));
      cairo_rectangle(cr, a, std::round(top), std::max(b - a, 1.0),
                      std::round(top + kTlBar * u) - std::round(top));
      set(cr, kGammaColour[int(run.gamma) % 3]);
      cairo_fill(cr);
    }
    cairo_restore(cr);
  }

  // Fading the future keeps the past vivid while the whole episode stays readable.
  if (frame_mode && dim_future && !cursors.empty() && !tl.rows.empty()) {
    const double cx = xt(cursors.front().time);
    if (bx1 > cx) {
      cairo_rectangle(cr, cx, rows_top, bx1 - cx, rows_bottom - rows_top);
      set(cr, kWhite, 0.55);
      cairo_fill(cr);
    }
  }

  // Time axis under the bars.
  const double axis_y = rows_bottom + 4 * u;
  set(cr, kFaintInk);
  cairo_set_line_width(cr, 1.0 * u);
  cairo_move_to(cr, bx0, axis_y);
  cairo_line_to(cr, bx0 + bw, axis_y);
  cairo_stroke(cr);
  const double step = nice_step(tl.t_end);
  TextStyle tick;
  tick.size = 10;
  tick.colour = kFaintInk;
  tick.align = 0.5;
  const long kmax = std::lround(std::floor(tl.t_end / step + 1e-9));
  for (long k = 0; k <= kmax; ++k) {
    const double tx = xt(k * step);
    set(cr, kFaintInk);
    cairo_move_to(cr, tx, axis_y);
    cairo_line_to(cr, tx, axis_y + 5 * u);
    cairo_stroke(cr);
    text(cr, u, number_text(k * step), tx, axis_y + 17 * u, tick);
  }
  tick.align = 1.0;
  text(cr, u, "time (s)", bx0 - 12 * u, axis_y + 17 * u, tick);

  // Cursors: a line through every row with a marker above it.
  for (const Cursor& c : cursors) {
    const double cx = xt(c.time);
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
  if (frame_mode && !cursors.empty()) {
    TextStyle st;
    st.size = 11;
    st.bold = true;
    for (size_t r = 0; r < tl.rows.size(); ++r) {
      const Gamma* g = tl.state_at(r, cursors.front().tick);
      const double base = rows_top + double(r) * kTlRow * u + bar_pad + 12.5 * u;
      // Darkened, since amber and green text on white read less well than the bars.
      st.colour = g && *g != Gamma::kNoRef ? darker(kGammaColour[int(*g) % 3], 0.8) : kFaintInk;
      text(cr, u, g ? gamma_name(*g) : "\u2013", bx1 + 12 * u, base, st);
    }
  }
  cairo_restore(cr);
  return {bx0, bx1, rows_top, rows_bottom};
}

// ---- files
// ----------------------------------------------------------------------------------------------

void write_text_file(const std::string& path, const std::string& content) {
  AtomicFile file(path, "animation: cannot write");
  file.append(content);
  file.commit();
}

constexpr int kMaxPicturePixels = 32767;  // cairo's image surface limit per side

// Owns a cairo surface and context for the length of one drawing.
struct Canvas {
  cairo_surface_t* surface = nullptr;
  cairo_t* cr = nullptr;
  ~Canvas() {
    if (cr) cairo_destroy(cr);
    if (surface) cairo_surface_destroy(surface);
  }
};

// Lets paint draw on a width x height image and writes it atomically to path as PNG.
template <class Paint>
void write_png(const std::string& path, long width, long height, Paint paint) {
  if (width < 1 || height < 1 || width > kMaxPicturePixels || height > kMaxPicturePixels) {
    std::ostringstream os;
    os << "animation: cannot write '" << path << "': a " << width << " x " << height
       << " picture is outside 1 to " << kMaxPicturePixels
       << " pixels per side (use a smaller frame width or fewer panels)";
    throw Error(os.str());
  }
  AtomicFile file(path, "animation: cannot write");
  Canvas canvas;
  canvas.surface = cairo_image_surface_create(CAIRO_FORMAT_ARGB32, int(width), int(height));
  check_cairo(file, cairo_surface_status(canvas.surface));
  canvas.cr = cairo_create(canvas.surface);
  set(canvas.cr, kWhite);
  cairo_paint(canvas.cr);
  paint(canvas.cr);
  check_cairo(file, cairo_status(canvas.cr));
  cairo_surface_flush(canvas.surface);
  check_cairo(file, cairo_surface_write_to_png_stream(canvas.surface, &cairo_write_to_file, &file));
  file.commit();
}

// frame_0000.png, ...; more digits only beyond 9999 frames.
std::string frame_name(size_t i) { return format("frame_%04zu.png", i); }

// The frame index a file name stands for, or -1 when it is not one of ours.
long frame_index(const std::string& name) {
  const std::string prefix = "frame_", suffix = ".png";
  if (name.size() <= prefix.size() + suffix.size() || name.compare(0, prefix.size(), prefix) != 0 ||
      name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0)
    return -1;
  const std::string digits =
      name.substr(prefix.size(), name.size() - prefix.size() - suffix.size());
  if (digits.size() > 9 ||
      !std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; }))
    return digits.size() > 9 ? LONG_MAX : -1;
  return std::stol(digits);
}

// Makes the folder (and its parents) or says why it cannot be used.
void make_folder(const std::string& folder) {
  if (folder.empty()) throw Error("animation: the output folder name is empty");
  std::error_code ec;
  if (fs::exists(folder, ec) && !fs::is_directory(folder, ec))
    throw Error("animation: cannot write into '" + folder + "': it exists and is not a folder");
  fs::create_directories(folder, ec);
  if (ec) throw Error("animation: cannot create folder '" + folder + "': " + ec.message());
}

// Everything that can be wrong with the inputs, found before any file is touched.
RenderOptions check_inputs(const WorldSpec& spec, const EpisodeResult& ep,
                           const AnimationOptions& o, const std::string& where) {
  if (ep.frames.empty())
    throw Error("animation: the episode has no frames to render into '" + where +
                "'; record them with EpisodeOptions::record_every > 0");
  if (!std::isfinite(o.fps) || o.fps <= 0 || o.fps > 1000)
    throw Error("animation: fps must be above 0 and at most 1000, got " + number_text(o.fps));
  for (size_t i = 0; i < ep.frames.size(); ++i) {
    const size_t n = ep.frames[i].objects.size();
    if (n != 0 && n != spec.objects.size())
      throw Error("animation: frame " + std::to_string(i) + " has " + std::to_string(n) +
                  " object poses but the world spec has " + std::to_string(spec.objects.size()) +
                  " objects: was the episode run in this world?");
  }
  RenderOptions fo = o.frame;
  if (fo.title.empty()) fo.title = o.title;
  fo.title = valid_utf8(fo.title);
  picture_size(spec, fo);  // throws for a bad width or an empty arena
  return fo;
}

// ---- episode.json and index.html
// --------------------------------------------------------------------------------

json pose_json(const Pose& p) { return {{"x", p.x}, {"y", p.y}, {"theta", p.theta}}; }

json episode_json(const WorldSpec& spec, const EpisodeResult& ep, const Timeline& tl,
                  const AnimationOptions& o) {
  json j;
  j["format"] = "roger-episode";
  j["version"] = 1;
  j["title"] = valid_utf8(o.title);
  j["scenario"] = {{"name", valid_utf8(spec.scenario)}, {"seed", spec.seed}};
  j["seed"] = ep.seed;
  j["success"] = ep.success;
  j["reward"] = ep.reward;
  j["sim_seconds"] = ep.sim_seconds;
  j["ticks"] = ep.ticks;
  j["tick_seconds"] = tl.dt;
  j["fps"] = o.fps;
  json names = json::array();
  for (const ObjectSpec& obj : spec.objects) names.push_back(valid_utf8(obj.name));
  j["objects"] = names;
  json frames = json::array();
  for (size_t i = 0; i < ep.frames.size(); ++i) {
    const Frame& f = ep.frames[i];
    json objects = json::array();
    for (const Pose& p : f.objects) objects.push_back(pose_json(p));
    frames.push_back({{"file", frame_name(i)},
                      {"tick", tl.frame_ticks[i]},
                      {"time", f.time},
                      {"base", pose_json(f.base)},
                      {"objects", objects}});
  }
  j["frames"] = frames;
  // One state name per control tick, in the words of the paper's Equation 1.
  json gammas = json::array();
  for (const GammaTrace& g : ep.gammas) {
    json states = json::array();
    for (Gamma s : g.states) states.push_back(gamma_name(s));
    gammas.push_back({{"name", valid_utf8(g.name)}, {"states", states}});
  }
  j["gammas"] = gammas;
  return j;
}

// Text for an HTML element or attribute.
std::string html_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default: out += c;
    }
  }
  return out;
}

// JSON safe to place inside a <script> element: '<' only occurs inside JSON strings, where \u003c
// means the same, so no name can close the element or open a comment.
std::string script_json(const json& j) {
  const std::string s = j.dump(-1, ' ', false, json::error_handler_t::replace);
  std::string out;
  out.reserve(s.size());
  for (char c : s) {
    if (c == '<')
      out += "\\u003c";
    else
      out += c;
  }
  return out;
}

// Replaces every {{key}} in the page template in one pass, so a title that happens to contain
// "{{DATA}}" stays text instead of being filled in itself.
std::string fill(const std::string& page,
                 const std::vector<std::pair<std::string, std::string>>& values) {
  std::string out;
  out.reserve(page.size());
  size_t at = 0;
  while (at < page.size()) {
    const size_t open = page.find("{{", at);
    const size_t close = open == std::string::npos ? open : page.find("}}", open + 2);
    if (close == std::string::npos) break;
    const std::string key = page.substr(open + 2, close - open - 2);
    const auto hit = std::find_if(values.begin(), values.end(),
                                  [&](const auto& kv) { return kv.first == key; });
    out.append(page, at, open - at);
    if (hit != values.end()) {
      out += hit->second;
      at = close + 2;
    } else {
      out += "{{";
      at = open + 2;
    }
  }
  out.append(page, std::min(at, page.size()), std::string::npos);
  return out;
}

// The replay page (web/episode.html, compiled in). Everything is inline so the folder can be
// zipped, mailed or opened from disk.
const char* const kPage = kEpisodePageHtml;

std::string page_html(const WorldSpec& spec, const EpisodeResult& ep, const Timeline& tl,
                      const AnimationOptions& o, const TimelineBox* box, double pic_w,
                      double pic_h) {
  json data;
  data["fps"] = o.fps;
  data["ticks"] = ep.ticks;
  data["sim_seconds"] = ep.sim_seconds;
  json frames = json::array();
  for (size_t i = 0; i < ep.frames.size(); ++i)
    frames.push_back({{"file", frame_name(i)},
                      {"time", std::isfinite(ep.frames[i].time) ? ep.frames[i].time : 0.0},
                      {"tick", tl.frame_ticks[i]}});
  data["frames"] = frames;
  // Each controller's state at each frame (-1 before the first tick), so the page needs no
  // knowledge of control ticks.
  json controllers = json::array();
  for (size_t r = 0; r < tl.rows.size(); ++r) {
    json states = json::array();
    for (long tick : tl.frame_ticks) {
      const Gamma* g = tl.state_at(r, tick);
      states.push_back(g ? int(*g) : -1);
    }
    controllers.push_back({{"name", tl.rows[r].name}, {"states", states}});
  }
  data["controllers"] = controllers;
  if (box)
    data["timeline"] = {{"x0", box->x0 / pic_w}, {"x1", box->x1 / pic_w},
                        {"y0", box->y0 / pic_h}, {"y1", box->y1 / pic_h},
                        {"t_end", tl.t_end}};
  else
    data["timeline"] = nullptr;

  const std::string title = valid_utf8(o.title);
  std::string meta = spec.scenario.empty() ? std::string("world")
                                           : "scenario " + valid_utf8(spec.scenario);
  meta += " \u00b7 world seed " + std::to_string(spec.seed) + " \u00b7 episode seed " +
          std::to_string(ep.seed) + " \u00b7 " + std::to_string(ep.frames.size()) + " frames";
  return fill(kPage, {{"TITLE", html_escape(title.empty() ? "roger episode"
                                                          : title + " \u2013 roger episode")},
                      {"HEADING", html_escape(title.empty() ? "Episode" : title)},
                      {"META", html_escape(meta)},
                      {"OUTCOME_CLASS", ep.success ? "success" : "timeout"},
                      {"OUTCOME", html_escape(outcome_text(tl))},
                      {"NOREF", kGammaCss[0]},
                      {"NOTCONV", kGammaCss[1]},
                      {"CONV", kGammaCss[2]},
                      {"DATA", script_json(data)}});
}

// Removes frame files a longer, earlier rendering left beyond the new count.
void remove_stale_frames(const std::string& folder, size_t count) {
  std::error_code ec;
  std::vector<fs::path> stale;
  for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    const long k = frame_index(name);
    if (k < 0) continue;
    if (size_t(k) >= count || name != frame_name(size_t(k))) stale.push_back(it->path());
  }
  if (ec) throw Error("animation: cannot list folder '" + folder + "': " + ec.message());
  for (const fs::path& p : stale) {
    fs::remove(p, ec);
    if (ec)
      throw Error("animation: cannot remove the old frame '" + p.string() +
                  "' (the folder would mix two episodes): " + ec.message());
  }
}

}  // namespace

void render_episode(const WorldSpec& spec, const EpisodeResult& episode, const std::string& folder,
                    const AnimationOptions& options) {
  const RenderOptions fo = check_inputs(spec, episode, options, folder);
  make_folder(folder);
  const Timeline tl = make_timeline(episode);
  const PictureSize world = picture_size(spec, fo);
  const double u = world.width / 1000.0;
  const double tl_h = options.show_timeline ? timeline_height(tl, TimelineMode::kFrame, u) : 0.0;
  const long width = world.width, height = world.height + long(std::ceil(tl_h));

  TimelineBox box;
  for (size_t i = 0; i < episode.frames.size(); ++i) {
    const Frame& f = episode.frames[i];
    write_png((fs::path(folder) / frame_name(i)).string(), width, height, [&](cairo_t* cr) {
      draw_frame(cr, spec, f, fo, world.width, world.height);
      if (options.show_timeline) {
        const Cursor c{std::isfinite(f.time) ? f.time : 0.0, 0, tl.frame_ticks[i]};
        box = draw_timeline(cr, tl, TimelineMode::kFrame, {c}, options.dim_future, 0,
                            world.height, world.width, u);
      }
    });
  }
  const fs::path dir(folder);
  write_text_file((dir / "episode.json").string(),
                  episode_json(spec, episode, tl, options)
                          .dump(1, ' ', false, json::error_handler_t::replace) +
                      "\n");
  // The page last: once it is replaced, every frame it names is already the new one.
  write_text_file((dir / "index.html").string(),
                  page_html(spec, episode, tl, options, options.show_timeline ? &box : nullptr,
                            double(width), double(height)));
  remove_stale_frames(folder, episode.frames.size());
}

void render_episode_summary(const WorldSpec& spec, const EpisodeResult& episode,
                            const std::string& path, const AnimationOptions& options, int panels) {
  std::string ext = fs::path(path).extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  if (ext != ".png")
    throw Error("animation: cannot write summary '" + path + "': the summary is a PNG, name it .png");
  if (panels < 1)
    throw Error("animation: a summary needs at least one panel, got " + std::to_string(panels));
  const RenderOptions fo = check_inputs(spec, episode, options, path);
  const Timeline tl = make_timeline(episode);

  // Evenly spaced in frame order, first and last included (frames are evenly spaced in time but
  // for the final one, taken when the goal held).
  const size_t count = episode.frames.size();
  const size_t n = std::min(size_t(panels), count);
  std::vector<size_t> pick;
  for (size_t i = 0; i < n; ++i)
    pick.push_back(n == 1 ? count - 1
                          : size_t(std::lround(double(i) * double(count - 1) / double(n - 1))));

  const PictureSize panel = picture_size(spec, fo);
  const double u = panel.width / 1000.0;
  const long width = long(panel.width) * long(n);
  const long height = panel.height + long(std::ceil(timeline_height(tl, TimelineMode::kSummary, u)));
  write_png(path, width, height, [&](cairo_t* cr) {
    std::vector<Cursor> cursors;
    for (size_t p = 0; p < n; ++p) {
      const Frame& f = episode.frames[pick[p]];
      cairo_save(cr);
      cairo_translate(cr, double(p) * panel.width, 0);
      draw_frame(cr, spec, f, fo, panel.width, panel.height);
      // The badge sits in the header's empty left corner, left of the title.
      number_badge(cr, u, 30 * u, 21 * u, int(p + 1));
      if (p > 0) {
        set(cr, kRule);
        cairo_set_line_width(cr, 1.0 * u);
        cairo_move_to(cr, 0.5 * u, 8 * u);
        cairo_line_to(cr, 0.5 * u, panel.height - 8 * u);
        cairo_stroke(cr);
      }
      cairo_restore(cr);
      cursors.push_back({std::isfinite(f.time) ? f.time : 0.0, int(p + 1), tl.frame_ticks[pick[p]]});
    }
    draw_timeline(cr, tl, TimelineMode::kSummary, cursors, false, 0, panel.height, double(width),
                  u);
  });
}

}  // namespace roger
