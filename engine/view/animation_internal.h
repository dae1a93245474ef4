// animation_internal.h: what the files of the episode animation share (private to view/): the
// timeline's colours and text helpers, the timeline computed from an episode and its drawing, and
// the writers of episode.json and index.html. animation.cpp writes the folder and the summary,
// timeline.cpp draws the timeline, episode_page.cpp fills the page.
#pragma once

#include <cairo.h>

#include <cstdio>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "control/control.h"
#include "core/spec.h"
#include "learn/episode.h"
#include "view/animation.h"
#include "view/ink.h"

namespace roger::anim {

using json = nlohmann::json;
using namespace ink;

// ---- colours and text
// -----------------------------------------------------------------------------------

// Beside the shared ink (ink.h): the timeline's own colours.
inline const Rgb kRule = rgb(218, 220, 226);
inline const Rgb kTrack = rgb(241, 242, 245);
inline const Rgb kSuccess = rgb(30, 130, 70);
inline const Rgb kFailure = rgb(190, 50, 40);

// State colours, also used by index.html (kept in step with kGammaCss below): grey for "nothing to
// do", amber for "working on it", green for "done", so a glance finds where a controller stalls.
inline const Rgb kGammaColour[3] = {rgb(178, 182, 190), rgb(240, 166, 0), rgb(44, 160, 84)};
inline const char* const kGammaCss[3] = {"#b2b6be", "#f0a600", "#2ca054"};
inline const char* const kGammaMeaning[3] = {"no reference", "descending", "converged"};

// printf-style formatting for labels (std::format is C++20).
template <class... Args>
std::string format(const char* fmt, Args... args) {
  char buf[200];
  std::snprintf(buf, sizeof buf, fmt, args...);
  return buf;
}

// A number without trailing zeros or a negative zero.
std::string number_text(double v);

// Names come from Lua scripts and may hold any bytes; cairo refuses invalid UTF-8 (and then draws
// nothing more), and the JSON writer would throw, so invalid bytes become '?'.
std::string valid_utf8(const std::string& s);

// ---- the episode as a timeline
// ----------------------------------------------------------------------------------

// One watched controller's states as runs of equal state, in seconds.
struct Run {
  double t0, t1;
  Gamma gamma;
};

// One watched controller: its name, its runs, and its state after each tick.
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

// The timeline of an episode: its clock, outcome, one row of runs per watched controller, and the
// tick of each frame.
Timeline make_timeline(const EpisodeResult& ep);

// "success after 3.42 s, reward 100" or "timeout after 5.00 s, reward -100".
std::string outcome_text(const Timeline& tl);

// ---- drawing the timeline (timeline.cpp)
// ----------------------------------------------------------------------------------

enum class TimelineMode { kFrame, kSummary };

// Height of the timeline band in device pixels, u device pixels per design unit.
double timeline_height(const Timeline& tl, TimelineMode mode, double u);

// A cursor on the timeline: a time and, in a summary, the panel number it belongs to.
struct Cursor {
  double time;
  int label;  // 0: none
  long tick;
};

// Where the bars go in the picture (the frame PNGs; the viewer draws its own timeline).
struct TimelineBox {
  double x0 = 0, x1 = 0, y0 = 0, y1 = 0;
};

// A filled circle with a white number: ties a summary panel to its moment on the timeline.
void number_badge(cairo_t* cr, double u, double x, double y, int n);

// Draws the timeline into the band (x, y)-(x + width, ...) of cr, u device pixels per design unit.
TimelineBox draw_timeline(cairo_t* cr, const Timeline& tl, TimelineMode mode,
                          const std::vector<Cursor>& cursors, bool dim_future, double x, double y,
                          double width, double u);

// ---- the folder's files
// ----------------------------------------------------------------------------------

// frame_0000.png, ...; more digits only beyond 9999 frames.
std::string frame_name(size_t i);

// episode.json: the world's shapes, every frame (poses, arms, eyes, images, touch), every tick's
// controller states and the decisions: all the viewer draws (episode_page.cpp).
json episode_json(const WorldSpec& spec, const EpisodeResult& ep, const Timeline& tl,
                  const AnimationOptions& o);

// index.html: the vector viewer with `episode` (episode_json's value) embedded (episode_page.cpp).
std::string page_html(const WorldSpec& spec, const EpisodeResult& ep, const Timeline& tl,
                      const AnimationOptions& o, const json& episode);

}  // namespace roger::anim
