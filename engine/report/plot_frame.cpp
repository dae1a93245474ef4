// plot_frame.cpp: the frame every figure is drawn in (see plot_internal.h): pen widths, tick
// steps, the plot area and its margins, the axes, the title and axis labels, and the legend.
#include <plplot.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "core/error.h"
#include "report/plot_internal.h"

namespace roger {
namespace plot_internal {
namespace {

// The legend's PLplot position flags.
PLINT legend_position(LegendPosition p) {
  constexpr PLINT kIn = PL_POSITION_INSIDE;
  switch (p) {
    case LegendPosition::kBottomLeft: return kIn | PL_POSITION_BOTTOM | PL_POSITION_LEFT;
    case LegendPosition::kTopRight: return kIn | PL_POSITION_TOP | PL_POSITION_RIGHT;
    case LegendPosition::kTopLeft: return kIn | PL_POSITION_TOP | PL_POSITION_LEFT;
    case LegendPosition::kOutsideRight: return PL_POSITION_OUTSIDE | PL_POSITION_RIGHT;
    case LegendPosition::kBottomRight:
    case LegendPosition::kBest: break;  // resolved by place_legend before drawing
  }
  return kIn | PL_POSITION_BOTTOM | PL_POSITION_RIGHT;
}

}  // namespace

// Sets the pen width, scaled with the page the way PLplot scales text.
void pen(double width) {
  PLFLT def_ht, ht;
  plgchr(&def_ht, &ht);
  plwidth(width * def_ht / kReferenceCharHeight);
}

// The plot area's size in character heights: {width, height}.
std::pair<double, double> viewport_chars() {
  PLFLT def_ht, ht, sx0, sx1, sy0, sy1, vx0, vx1, vy0, vy1;
  plgchr(&def_ht, &ht);
  plgspa(&sx0, &sx1, &sy0, &sy1);
  plgvpd(&vx0, &vx1, &vy0, &vy1);
  return {(vx1 - vx0) * (sx1 - sx0) / ht, (vy1 - vy0) * (sy1 - sy0) / ht};
}

// How many x ticks fit along `chars` character heights when labels are up to `label_chars` long.
int x_tick_target(double chars, double label_chars) {
  return std::max(2, std::min(6, int(chars / (0.65 * label_chars + 2.5))));
}

// How many y ticks fit along `chars` character heights.
int y_tick_target(double chars) { return std::max(2, std::min(6, int(chars / 2.5))); }

// The length in characters of the longest tick label PLplot may print for values in [lo, hi].
double label_chars(double lo, double hi) {
  const double m = std::max(std::abs(lo), std::abs(hi));
  double chars = m >= 1.0 ? std::floor(std::log10(m)) + 1.0 : 3.0;
  if (lo < 0.0) chars += 1.0;
  return std::min(chars, 6.0);  // PLplot switches to a scale factor beyond this
}

// A round tick interval (1, 2 or 5 times a power of ten) giving about `target` ticks over span.
double nice_step(double span, int target) {
  const double raw = span / target;
  const double power = std::pow(10.0, std::floor(std::log10(raw)));
  const double f = raw / power;
  return (f < 1.5 ? 1.0 : f < 3.5 ? 2.0 : f < 7.5 ? 5.0 : 10.0) * power;
}

// Axes: ticks and numbers on the bottom and left edges only, the top and right edges plain.
void draw_axes(const std::string& x_opt, double x_step, double y_step) {
  plcol0(kInk);
  pen(1.0);
  plbox(("b" + x_opt).c_str(), x_step, 0, "bnstv", y_step, 0);
  plbox("c", 0.0, 0, "c", 0.0, 0);
}

// The right margin in character heights: a little air, or room for a legend beside the plot
// (sized by the longest entry).
double right_margin(LegendPosition legend, const std::vector<std::string>& names) {
  if (legend != LegendPosition::kOutsideRight) return 1.7;
  size_t longest = 0;
  for (const auto& name : names) longest = std::max(longest, name.size());
  return 8.5 + 0.62 * double(longest);
}

// The plot area, leaving margins (in character heights, which PLplot scales with the page) for
// tick labels, axis labels, the title and the legend. Throws when the plot would be too narrow.
void set_viewport(double right) {
  PLFLT def_ht, ht, x0, x1, y0, y1;
  plgchr(&def_ht, &ht);
  plgspa(&x0, &x1, &y0, &y1);
  const double w = x1 - x0, h = y1 - y0;
  const double left = 5.6 * ht / w, right_frac = right * ht / w;
  if (1.0 - left - right_frac < 0.3)
    throw Error("plot: the figure is too narrow to hold its legend beside the plot; widen it, "
                "shorten the names or put the legend inside");
  plvpor(left, 1.0 - right_frac, 4.4 * ht / h, 1.0 - 3.5 * ht / h);
}

std::string fitted_title(const std::string& title, double width_mm, double char_height_mm) {
  const size_t room = size_t(std::max(8.0, 0.96 * width_mm / (0.85 * char_height_mm)));
  size_t chars = 0, cut = 0;  // characters, and the byte where the room for room - 1 of them ends
  for (size_t k = 0; k < title.size(); ++k) {
    if ((static_cast<unsigned char>(title[k]) & 0xC0) == 0x80) continue;  // inside a UTF-8 character
    if (chars == room - 1) cut = k;
    ++chars;
  }
  return chars <= room ? title : title.substr(0, cut) + "\u2026";
}

// Title above the plot area and the two axis labels.
void draw_labels(const std::string& title, const std::string& x_label, const std::string& y_label) {
  plcol0(kInk);
  plschr(0.0, 1.05);
  plmtex("b", 3.0, 0.5, 0.5, plain(x_label).c_str());
  plmtex("l", 4.2, 0.5, 0.5, plain(y_label).c_str());
  if (!title.empty()) {
    plsfont(PL_FCI_SANS, PL_FCI_UPRIGHT, PL_FCI_BOLD);
    plschr(0.0, 1.3);
    PLFLT def_ht, ht, x0, x1, y0, y1;
    plgchr(&def_ht, &ht);
    plgspa(&x0, &x1, &y0, &y1);
    plmtex("t", 1.6, 0.5, 0.5, plain(fitted_title(title, x1 - x0, ht)).c_str());
    plsfont(PL_FCI_SANS, PL_FCI_UPRIGHT, PL_FCI_MEDIUM);
  }
  plschr(0.0, 1.0);
}

namespace {

// The characters of a UTF-8 text (a legend entry's width).
size_t text_chars(const std::string& text) {
  return size_t(std::count_if(text.begin(), text.end(), [](char c) { return (static_cast<unsigned char>(c) & 0xC0) != 0x80; }));
}

// The box a legend of `names` takes in `corner` of the plot area, in its fractions {x0, x1, y0,
// y1}: draw_legend's offsets (0.02, 0.03), its symbol (0.06 of the width), each entry two
// character heights, its text 0.62 of a height per character, and some air.
std::vector<double> legend_box(LegendPosition corner, const std::vector<std::string>& names) {
  const auto [w, h] = viewport_chars();
  size_t longest = 0;
  for (const auto& name : names) longest = std::max(longest, text_chars(name));
  const double bw = 0.06 + (3.0 + 0.62 * double(longest)) / w, bh = (2.0 * double(names.size()) + 1.0) / h;
  const bool right = corner == LegendPosition::kBottomRight || corner == LegendPosition::kTopRight;
  const bool top = corner == LegendPosition::kTopRight || corner == LegendPosition::kTopLeft;
  const double x0 = right ? 1.0 - 0.02 - bw : 0.02, y0 = top ? 1.0 - 0.03 - bh : 0.03;
  return {x0, x0 + bw, y0, y0 + bh};
}

}  // namespace

LegendPosition place_legend(LegendPosition wanted, const std::vector<std::string>& names, const DataCover& cover,
                            const std::vector<LegendPosition>& order) {
  set_viewport(right_margin(wanted, names));
  if (wanted != LegendPosition::kBest) return wanted;
  LegendPosition best = order.front();
  double least = INFINITY;
  for (LegendPosition corner : order) {
    const std::vector<double> b = legend_box(corner, names);
    const double covered = cover(b[0], b[1], b[2], b[3]);
    if (covered < least) least = covered, best = corner;
  }
  if (least <= 0.0) return best;
  try {  // every corner hides some data: beside the plot, if the figure is wide enough
    set_viewport(right_margin(LegendPosition::kOutsideRight, names));
    return LegendPosition::kOutsideRight;
  } catch (const Error&) {
    set_viewport(right_margin(best, names));
    return best;
  }
}

// A legend of n entries; `lines` draws a line over each colour box (learning curves).
void draw_legend(const std::vector<std::string>& names, const std::vector<PLINT>& line_colours,
                 const std::vector<PLINT>& box_colours, bool lines, LegendPosition position) {
  const size_t n = names.size();
  std::vector<std::string> texts;
  for (const auto& name : names) texts.push_back(plain(name));
  std::vector<const char*> text_ptrs, symbols(n, "");
  for (const auto& t : texts) text_ptrs.push_back(t.c_str());
  std::vector<PLINT> opts(n, PL_LEGEND_COLOR_BOX | (lines ? PL_LEGEND_LINE : 0));
  std::vector<PLINT> text_colours(n, kInk), patterns(n, 0), styles, zeros(n, 0);
  for (size_t i = 0; i < n; ++i) styles.push_back(lines ? line_style(i) : 1);
  PLFLT def_ht, ht;
  plgchr(&def_ht, &ht);
  std::vector<PLFLT> box_scales(n, lines ? 0.9 : 0.8), box_widths(n, 1.0),
      line_widths(n, 2.5 * ht / kReferenceCharHeight), symbol_scales(n, 1.0);
  PLFLT legend_width = 0, legend_height = 0;
  plschr(0.0, 1.0);
  pllegend(&legend_width, &legend_height, PL_LEGEND_BACKGROUND | PL_LEGEND_BOUNDING_BOX,
           legend_position(position), 0.02, 0.03, 0.06, kBackground, kFrame, 1, 0, 0, PLINT(n),
           opts.data(), 1.0, 1.0, 2.0, 0.0, text_colours.data(), text_ptrs.data(),
           box_colours.data(), patterns.data(), box_scales.data(), box_widths.data(),
           line_colours.data(), styles.data(), line_widths.data(), zeros.data(),
           symbol_scales.data(), zeros.data(), symbols.data());
}

}  // namespace plot_internal
}  // namespace roger
