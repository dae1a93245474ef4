// plot_curves.cpp: learning curves (see plot.h): the series are checked, the world window is
// fitted to them, and each is drawn as a translucent band (mean +- std, or its own low..high)
// under its line.
#include <plplot.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/error.h"
#include "report/plot.h"
#include "report/plot_internal.h"

namespace roger {

using namespace plot_internal;

namespace {

// Throws unless a series' own band (low..high) is one pair of bounds per x, in order.
void check_band(const CurveSeries& c, const std::string& who) {
  if (c.low.empty() && c.high.empty()) return;
  if (!c.std.empty())
    throw Error("plot: " + who + " has both a std and a low..high band; give one or the other");
  if (c.low.size() != c.x.size() || c.high.size() != c.x.size())
    throw Error("plot: " + who + " has " + std::to_string(c.x.size()) + " x values but " +
                std::to_string(c.low.size()) + " band lows and " + std::to_string(c.high.size()) +
                " band highs (give one of each per x, or none)");
  check_finite(c.low, who + " low");
  check_finite(c.high, who + " high");
  for (size_t i = 0; i < c.x.size(); ++i)
    if (c.low[i] > c.high[i])
      throw Error("plot: " + who + " low[" + std::to_string(i) + "] = " + number(c.low[i]) +
                  " is above high[" + std::to_string(i) + "] = " + number(c.high[i]));
}

// Whether a series has a band to draw, and its bounds at point i (mean +- std, or low..high).
bool has_band(const CurveSeries& c) { return !c.std.empty() || !c.low.empty(); }
double band_low(const CurveSeries& c, size_t i) {
  return !c.low.empty() ? c.low[i] : c.std.empty() ? c.mean[i] : c.mean[i] - c.std[i];
}
double band_high(const CurveSeries& c, size_t i) {
  return !c.high.empty() ? c.high[i] : c.std.empty() ? c.mean[i] : c.mean[i] + c.std[i];
}

// Throws unless the series and the options make a drawable figure, naming the first problem.
void check_series(const std::vector<CurveSeries>& series, const CurveOptions& o) {
  if (series.empty()) throw Error("plot: learning curves need at least one series, got none");
  for (size_t s = 0; s < series.size(); ++s) {
    const CurveSeries& c = series[s];
    const std::string who = "series " + std::to_string(s) + " ('" + c.name + "')";
    if (c.x.empty()) throw Error("plot: " + who + " has no points");
    if (c.mean.size() != c.x.size())
      throw Error("plot: " + who + " has " + std::to_string(c.x.size()) + " x values but " +
                  std::to_string(c.mean.size()) + " means");
    if (!c.std.empty() && c.std.size() != c.x.size())
      throw Error("plot: " + who + " has " + std::to_string(c.x.size()) + " x values but " +
                  std::to_string(c.std.size()) + " standard deviations (give one per x, or none)");
    check_finite(c.x, who + " x");
    check_finite(c.mean, who + " mean");
    check_finite(c.std, who + " std");
    check_band(c, who);
    for (size_t i = 0; i < c.std.size(); ++i)
      if (c.std[i] < 0.0)
        throw Error("plot: " + who + " std[" + std::to_string(i) + "] is " + number(c.std[i]) +
                    ", expected a value >= 0");
    for (size_t i = 1; i < c.x.size(); ++i)
      if (c.x[i] < c.x[i - 1])
        throw Error("plot: " + who + " x[" + std::to_string(i) + "] = " + number(c.x[i]) +
                    " is below x[" + std::to_string(i - 1) + "] = " + number(c.x[i - 1]) +
                    "; the x values must be in increasing order");
    if (o.log_x)
      for (size_t i = 0; i < c.x.size(); ++i)
        if (!(c.x[i] > 0.0))
          throw Error("plot: " + who + " x[" + std::to_string(i) + "] is " + number(c.x[i]) +
                      ", but a log-scale x axis needs every x > 0 (drop the point or turn off "
                      "log_x)");
  }
  if (!std::isfinite(o.y_min) || !std::isfinite(o.y_max) || !(o.y_min < o.y_max))
    throw Error("plot: the y range [" + number(o.y_min) + ", " + number(o.y_max) +
                "] is empty; y_min must be below y_max");
  if (!(o.band_alpha >= 0.0 && o.band_alpha <= 1.0))
    throw Error("plot: band_alpha is " + number(o.band_alpha) + ", expected a value in [0, 1]");
}

// The world window of the curves: x over the data (whole decades on a log axis), y over the asked
// range widened to the data, with a margin.
struct CurveWindow {
  double x_lo, x_hi, y_lo, y_hi;
};

// Fits the world window to the series.
CurveWindow curve_window(const std::vector<CurveSeries>& series, const CurveOptions& o) {
  double x_lo = series[0].x.front(), x_hi = series[0].x.back();
  double y_lo = o.y_min, y_hi = o.y_max;
  for (const auto& c : series) {
    x_lo = std::min(x_lo, c.x.front());
    x_hi = std::max(x_hi, c.x.back());
    if (!o.fit_data) continue;
    for (size_t i = 0; i < c.x.size(); ++i) {
      y_lo = std::min({y_lo, c.mean[i], band_low(c, i)});
      y_hi = std::max({y_hi, c.mean[i], band_high(c, i)});
    }
  }
  if (o.log_x) {
    x_lo = std::floor(std::log10(x_lo) + 1e-9);
    x_hi = std::ceil(std::log10(x_hi) - 1e-9);
    if (x_hi <= x_lo) x_hi = x_lo + 1.0;
  } else if (x_hi <= x_lo) {
    const double pad = x_lo == 0.0 ? 1.0 : std::abs(x_lo) * 0.1;
    x_lo -= pad;
    x_hi += pad;
  }
  const double y_pad = 0.06 * (y_hi - y_lo);
  y_lo -= y_pad;
  y_hi += y_pad;
  return {x_lo, x_hi, y_lo, y_hi};
}

// A data x in world coordinates (its log10 on a log axis).
double world_x(double x, const CurveOptions& o) { return o.log_x ? std::log10(x) : x; }

// The cmap0 entry of series s's line.
PLINT line_index(size_t s) { return PLINT(kFirstSeries + s); }

// The cmap0 entry of series s's band, after the n lines' entries.
PLINT band_index(size_t n, size_t s) { return PLINT(kFirstSeries + n + s); }

// The translucent band of every series that has one.
void draw_bands(const std::vector<CurveSeries>& series, const CurveOptions& o) {
  const size_t n = series.size();
  for (size_t s = 0; s < n; ++s) {
    const CurveSeries& c = series[s];
    if (!has_band(c) || o.band_alpha == 0.0) continue;
    std::vector<PLFLT> bx, by;
    for (size_t i = 0; i < c.x.size(); ++i) {
      bx.push_back(world_x(c.x[i], o));
      by.push_back(band_high(c, i));
    }
    for (size_t i = c.x.size(); i-- > 0;) {
      bx.push_back(world_x(c.x[i], o));
      by.push_back(band_low(c, i));
    }
    plcol0(band_index(n, s));
    if (bx.size() >= 3) plfill(PLINT(bx.size()), bx.data(), by.data());
  }
}

// The mean line of every series (a dot with an error bar for a series of one point).
void draw_mean_lines(const std::vector<CurveSeries>& series, const CurveOptions& o) {
  pen(2.2);
  for (size_t s = 0; s < series.size(); ++s) {
    const CurveSeries& c = series[s];
    std::vector<PLFLT> lx, ly(c.mean.begin(), c.mean.end());
    for (double x : c.x) lx.push_back(world_x(x, o));
    plcol0(line_index(s));
    pllsty(line_style(s));
    if (lx.size() > 1) {
      plline(PLINT(lx.size()), lx.data(), ly.data());
      continue;
    }
    // A single point: a dot with an error bar over its band instead of a line and a band.
    if (has_band(c)) {
      PLFLT lo = band_low(c, 0), hi = band_high(c, 0);
      plerry(1, lx.data(), &lo, &hi);
    }
    plstring(1, lx.data(), ly.data(), "\u25CF");
  }
  pllsty(1);
}

// The legend: each series' line over its band's colour (the background when it has no band).
void draw_curve_legend(const std::vector<CurveSeries>& series,
                       const std::vector<std::string>& names, LegendPosition position) {
  const size_t n = series.size();
  std::vector<PLINT> lines, boxes;
  for (size_t s = 0; s < n; ++s) {
    lines.push_back(line_index(s));
    boxes.push_back(has_band(series[s]) ? band_index(n, s) : kBackground);
  }
  draw_legend(names, lines, boxes, true, position);
}

// How much of the curves lies in a box of the plot area (its fractions): the mean lines' points
// (and points between them, so a steep line crossing the box counts), and the bands' at half
// weight where the box's height meets them.
DataCover curve_cover(const std::vector<CurveSeries>& series, const CurveWindow& w, const CurveOptions& o) {
  return [&series, w, o](double x0, double x1, double y0, double y1) {
    const auto fx = [&](double x) { return (world_x(x, o) - w.x_lo) / (w.x_hi - w.x_lo); };
    const auto fy = [&](double y) { return (y - w.y_lo) / (w.y_hi - w.y_lo); };
    double covered = 0.0;
    for (const CurveSeries& c : series)
      for (size_t i = 0; i < c.x.size(); ++i) {
        const double xa = fx(c.x[i]), ya = fy(c.mean[i]);
        const double xb = i + 1 < c.x.size() ? fx(c.x[i + 1]) : xa, yb = i + 1 < c.x.size() ? fy(c.mean[i + 1]) : ya;
        for (int k = 0; k < 8; ++k) {
          const double t = k / 8.0, x = xa + t * (xb - xa), y = ya + t * (yb - ya);
          covered += x >= x0 && x <= x1 && y >= y0 && y <= y1;
        }
        if (has_band(c) && xa >= x0 && xa <= x1 && fy(band_low(c, i)) <= y1 && fy(band_high(c, i)) >= y0)
          covered += 0.5;
      }
    return covered;
  };
}

}  // namespace

LegendPosition plot_learning_curves(const std::string& path, const std::string& title,
                                    const std::vector<CurveSeries>& series, const CurveOptions& options) {
  return plot_learning_curves(std::vector<std::string>{path}, title, series, options);
}

LegendPosition plot_learning_curves(const std::vector<std::string>& paths, const std::string& title,
                          const std::vector<CurveSeries>& series, const CurveOptions& o) {
  check_series(series, o);
  for (const auto& p : paths) format_of(p);

  // World window: x over the data (whole decades on a log axis), y over the asked range.
  const CurveWindow w = curve_window(series, o);

  const size_t n = series.size();
  std::vector<std::string> names;
  for (const auto& c : series) names.push_back(c.name);
  const PLINT colours = PLINT(kFirstSeries + 2 * n);
  LegendPosition placed = o.legend;

  draw_figure(paths, o.width_px, o.height_px, colours, [&] {
    for (size_t s = 0; s < n; ++s) {
      const Colour c = plot_colour(series[s].colour < 0 ? s : size_t(series[s].colour));
      plscol0a(line_index(s), c.r, c.g, c.b, 1.0);
      plscol0a(band_index(n, s), c.r, c.g, c.b, o.band_alpha);
    }
    // Curves that learn rise to the right: the bottom right is most often free.
    const LegendPosition legend = placed =
        place_legend(o.legend, names, curve_cover(series, w, o),
                     {LegendPosition::kBottomRight, LegendPosition::kTopLeft, LegendPosition::kBottomLeft,
                      LegendPosition::kTopRight});
    plwind(w.x_lo, w.x_hi, w.y_lo, w.y_hi);
    const std::string x_axis = o.log_x ? "l" : "";

    const auto chars = viewport_chars();
    const double x_step = o.log_x ? 0.0
                                  : nice_step(w.x_hi - w.x_lo,
                                              x_tick_target(chars.first, label_chars(w.x_lo, w.x_hi)));
    const double y_step = nice_step(w.y_hi - w.y_lo, y_tick_target(chars.second));
    plcol0(kGrid);
    pen(1.0);
    plbox(("g" + x_axis).c_str(), x_step, 0, "g", y_step, 0);

    draw_bands(series, o);
    draw_mean_lines(series, o);

    draw_axes("nst" + x_axis, x_step, y_step);
    draw_labels(title, o.x_label, o.y_label);
    draw_curve_legend(series, names, legend);
  });
  return placed;
}

}  // namespace roger
