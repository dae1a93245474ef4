// plot.h: the paper's figures, drawn with PLplot's cairo driver (devices "pngcairo" and
// "svgcairo") to PNG and SVG files: learning curves with mean +- std bands (Figures 3 and 4, log x
// for Figure 4) or with confidence bands (the IQM figures), stacked bars of cumulative training
// time (Figure 5), and heat maps (where a teacher sampled a parameter over training).
//
// Each path's extension (.png or .svg, any case) chooses its format. Files are written atomically:
// PLplot draws into a temporary file beside the destination, which is checked to be a complete
// PNG or SVG and then renamed over it, so a destination either keeps its old content or gets the
// whole new figure; a failure throws roger::Error and leaves no file behind. Several paths in one
// call are all drawn before any is renamed into place.
//
// PLplot keeps global state and is not thread-safe: every figure takes one process-wide mutex and
// runs plinit ... plend on its own. PLplot's fatal-error hook is redirected to a roger::Error for
// the length of a figure, so a PLplot failure never exits the process.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "core/spec.h"

namespace roger {

// One learning curve: mean +- std of the episodic reward against training time, or any centre line
// with its own band (an interquartile mean inside its bootstrap interval).
struct CurveSeries {
  std::string name;          // legend entry, e.g. "DC2"
  std::vector<double> x;     // training time, increasing (the unit is named by x_label)
  std::vector<double> mean;  // the line: mean over trials at each x (or the IQM, with low/high)
  std::vector<double> std;   // std over trials at each x, >= 0; empty for no band
  // An asymmetric band instead of mean +- std: low[i] <= high[i] at each x (e.g. a 95% confidence
  // interval). Both empty for none; when given, std must be empty.
  std::vector<double> low, high;
  // The palette entry it is drawn in (plot_colour); -1: its place among the series. A figure gives
  // each curve its place in the figure's full list, so a curve keeps its colour when others lack data.
  int colour = -1;
};

// Where the legend sits: in a corner of the plot area, or beside it on the right (for busy plots).
// kBest: the inside corner the data covers least (curves prefer the bottom right, bars the top
// right, on ties), or beside the plot when the data reaches into every corner.
enum class LegendPosition { kBottomRight, kBottomLeft, kTopRight, kTopLeft, kOutsideRight, kBest };

// How plot_learning_curves draws.
struct CurveOptions {
  std::string x_label = "Training time (min)";
  std::string y_label = "Average episodic reward";
  bool log_x = false;          // log10 x axis over whole decades (Figure 4); every x must be > 0
  double y_min = -100.0;       // the y range always shown (the paper's rewards are in [-100, 100])
  double y_max = 100.0;
  bool fit_data = true;        // widen the y range to every mean +- std (else clip to it)
  double band_alpha = 0.2;     // opacity of the mean +- std bands, in [0, 1]
  int width_px = 1000;         // PNG size in pixels (SVG: the same size in points)
  int height_px = 650;
  LegendPosition legend = LegendPosition::kBest;
};

// One part of every stacked bar (Figure 5: "SG" and "T").
struct BarStack {
  std::string name;            // legend entry
  std::vector<double> values;  // one value >= 0 per category, stacked in the order of the stacks
  // Per category (empty: none): the value is only a lower bound (a mean over training times some
  // of which never reached the threshold), labelled "≥ " as is the bar's total.
  std::vector<bool> lower_bound;
};

// How plot_stacked_bars draws.
struct BarOptions {
  std::string y_label = "Cumulative training time (min)";
  // Text of a value label; empty means "%.4g". Figure 5: minutes as min:sec through
  // [](double m) { return format_min_sec(60 * m); }.
  std::function<std::string(double)> value_label;
  bool part_labels = true;   // label each part that is tall enough to hold its text
  bool total_labels = true;  // label each bar's total above it
  int width_px = 1000;
  int height_px = 650;
  LegendPosition legend = LegendPosition::kBest;
};

// A heat map: a share in [0, 1] per cell of a grid of columns (bins of the x axis) and rows
// (labelled values, bottom to top). Where a teacher sampled a parameter against training episodes.
struct HeatMap {
  std::vector<double> x_edges;             // the columns' edges, increasing (columns + 1 of them)
  std::vector<std::string> rows;           // the rows' labels, bottom to top
  std::vector<std::vector<double>> share;  // [row][column], each in [0, 1]
};

// How plot_heat_map draws.
struct HeatOptions {
  std::string x_label = "Training episodes";
  std::string y_label;
  int width_px = 1000;
  int height_px = 650;
};

// Draws the heat map to every path (e.g. one .png and one .svg), shaded in ten steps from white
// (0) to deep blue (1) with a key beside it.
void plot_heat_map(const std::vector<std::string>& paths, const std::string& title, const HeatMap& map,
                   const HeatOptions& options = HeatOptions());

// The colour of the index-th series or stack (a colour-blind-safe palette, cycled).
Colour plot_colour(size_t index);

// Draws learning curves (a line per series over a translucent mean +- std band) to path.
// Returns where the legend went (kBest resolved to a corner or beside the plot).
LegendPosition plot_learning_curves(const std::string& path, const std::string& title,
                          const std::vector<CurveSeries>& series,
                          const CurveOptions& options = CurveOptions());

// Draws the same learning curves to every path (e.g. one .png and one .svg); pass a named vector.
LegendPosition plot_learning_curves(const std::vector<std::string>& paths, const std::string& title,
                          const std::vector<CurveSeries>& series,
                          const CurveOptions& options = CurveOptions());

// Draws one stacked bar per category (an approach), split into the stacks, to path. Returns where
// the legend went.
LegendPosition plot_stacked_bars(const std::string& path, const std::string& title,
                       const std::vector<std::string>& categories,
                       const std::vector<BarStack>& stacks,
                       const BarOptions& options = BarOptions());

// Draws the same stacked bars to every path (e.g. one .png and one .svg); pass a named vector.
LegendPosition plot_stacked_bars(const std::vector<std::string>& paths, const std::string& title,
                       const std::vector<std::string>& categories,
                       const std::vector<BarStack>& stacks,
                       const BarOptions& options = BarOptions());

}  // namespace roger
