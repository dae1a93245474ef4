// plot_internal.h: what the figure files of the report module share (not part of plot.h's API):
// writing a figure through PLplot (plot.cpp), the frame every figure is drawn in: axes, tick
// steps, margins, labels and legend (plot_frame.cpp), used by the learning curves
// (plot_curves.cpp) and the stacked bars (plot_bars.cpp).
#pragma once

#include <plplot.h>

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "report/plot.h"

namespace roger {
namespace plot_internal {

// ---- Writing a figure (plot.cpp) ----

enum class Format { kPng, kSvg };

// The format named by path's extension, or an Error naming the two accepted ones.
Format format_of(const std::string& path);

// Draws the figure once per path (each into a checked temporary), then renames them all.
void draw_figure(const std::vector<std::string>& paths, int width, int height, PLINT colours,
                 const std::function<void()>& draw);

// Line style of the index-th series: solid, then dashed patterns once the palette repeats.
PLINT line_style(size_t index);

// Fixed cmap0 entries; series colours follow from kFirstSeries.
enum : PLINT { kBackground = 0, kInk = 1, kGrid = 2, kFrame = 3, kWhite = 4, kFirstSeries = 5 };

// PLplot text with its escape character doubled, so '#' in a name is printed as itself.
std::string plain(const std::string& text);

// A title for a figure `width_mm` wide in characters `char_height_mm` high: whole, or cut at a
// character's boundary with an ellipsis when it would not fit (PLplot centres a title and crops
// both its ends; found by a probe). PLplot has no public measure of text: a bold sans character
// is taken as 0.85 of its height wide (DejaVu Sans Bold averages about 0.8).
std::string fitted_title(const std::string& title, double width_mm, double char_height_mm);

// A value as an error message shows it.
std::string number(double v);

// Throws unless every value is finite; `what` names the values for the message.
void check_finite(const std::vector<double>& values, const std::string& what);

// ---- The frame of a figure (plot_frame.cpp) ----

// PLplot's character height in millimetres on a 1000 x 650 page, where widths were tuned.
constexpr double kReferenceCharHeight = 5.82;

// Sets the pen width, scaled with the page the way PLplot scales text.
void pen(double width);

// The plot area's size in character heights: {width, height}.
std::pair<double, double> viewport_chars();

// How many x ticks fit along `chars` character heights when labels are up to `label_chars` long.
int x_tick_target(double chars, double label_chars);

// How many y ticks fit along `chars` character heights.
int y_tick_target(double chars);

// The length in characters of the longest tick label PLplot may print for values in [lo, hi].
double label_chars(double lo, double hi);

// A round tick interval (1, 2 or 5 times a power of ten) giving about `target` ticks over span.
double nice_step(double span, int target);

// Axes: ticks and numbers on the bottom and left edges only, the top and right edges plain.
void draw_axes(const std::string& x_opt, double x_step, double y_step);

// The right margin in character heights: a little air, or room for a legend beside the plot
// (sized by the longest entry).
double right_margin(LegendPosition legend, const std::vector<std::string>& names);

// The plot area, leaving margins (in character heights, which PLplot scales with the page) for
// tick labels, axis labels, the title and the legend. Throws when the plot would be too narrow.
void set_viewport(double right);

// Title above the plot area and the two axis labels.
void draw_labels(const std::string& title, const std::string& x_label, const std::string& y_label);

// How much of the data lies in a box of the plot area, given in its fractions (x0, x1, y0, y1 in
// [0, 1], left to right and bottom to top): 0 when none does.
using DataCover = std::function<double(double x0, double x1, double y0, double y1)>;

// Sets the plot area (set_viewport) and resolves `wanted`: kBest becomes the first of the
// inside corners `order` whose legend box (for `names`, as draw_legend draws them) covers the
// least data, or kOutsideRight, with the plot area narrowed for it, when every corner covers some
// and the figure is wide enough. Other positions are kept. Call before plwind.
LegendPosition place_legend(LegendPosition wanted, const std::vector<std::string>& names, const DataCover& cover,
                            const std::vector<LegendPosition>& order);

// A legend of n entries; `lines` draws a line over each colour box (learning curves).
void draw_legend(const std::vector<std::string>& names, const std::vector<PLINT>& line_colours,
                 const std::vector<PLINT>& box_colours, bool lines, LegendPosition position);

}  // namespace plot_internal
}  // namespace roger
