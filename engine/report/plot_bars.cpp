// plot_bars.cpp: stacked bars (see plot.h): the stacks are checked, the value labels are
// written before PLplot starts, and each bar is drawn part by part with its labels.
#include <plplot.h>

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "core/error.h"
#include "report/plot.h"
#include "report/plot_internal.h"

namespace roger {

using namespace plot_internal;

namespace {

// Half a bar's width in world units (a category is one unit wide).
constexpr double kBarHalf = 0.31;

// Throws unless there are categories and stacks, with one finite value >= 0 per category each.
void check_bars(const std::vector<std::string>& categories, const std::vector<BarStack>& stacks) {
  if (categories.empty()) throw Error("plot: stacked bars need at least one category, got none");
  if (stacks.empty()) throw Error("plot: stacked bars need at least one stack, got none");
  for (size_t k = 0; k < stacks.size(); ++k) {
    const BarStack& st = stacks[k];
    const std::string who = "stack " + std::to_string(k) + " ('" + st.name + "')";
    if (st.values.size() != categories.size())
      throw Error("plot: " + who + " has " + std::to_string(st.values.size()) +
                  " values for " + std::to_string(categories.size()) +
                  " categories; give one value per category");
    check_finite(st.values, who + " values");
    for (size_t i = 0; i < st.values.size(); ++i)
      if (st.values[i] < 0.0)
        throw Error("plot: " + who + " values[" + std::to_string(i) + "] is " +
                    number(st.values[i]) + "; stacked bars need values >= 0");
  }
}

// The value labels of the bars, as PLplot text; an empty text is not drawn.
struct BarTexts {
  std::vector<std::vector<std::string>> part;  // [stack][category]
  std::vector<std::string> total;              // [category]
};

// The labels of every part and total the options ask for.
BarTexts bar_texts(const std::vector<BarStack>& stacks, const std::vector<double>& totals,
                   const BarOptions& o) {
  const size_t n_cat = totals.size(), n_stack = stacks.size();
  const auto label = [&](double v) {
    if (o.value_label) return o.value_label(v);
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.4g", v);
    return std::string(buf);
  };
  const auto bound = [&](size_t k, size_t i) {
    return i < stacks[k].lower_bound.size() && stacks[k].lower_bound[i] ? std::string("≥ ") : std::string();
  };
  std::vector<std::vector<std::string>> part_text(n_stack, std::vector<std::string>(n_cat));
  std::vector<std::string> total_text(n_cat);
  for (size_t i = 0; i < n_cat; ++i) {
    size_t parts = 0;
    for (const auto& st : stacks) parts += st.values[i] > 0.0 ? 1 : 0;
    // A bar of one part has its value above it already when totals are labelled.
    if (!o.part_labels || (parts == 1 && o.total_labels)) continue;
    for (size_t k = 0; k < n_stack; ++k) part_text[k][i] = plain(bound(k, i) + label(stacks[k].values[i]));
  }
  for (size_t i = 0; i < n_cat; ++i) {
    std::string lower;
    for (size_t k = 0; k < n_stack; ++k) lower = lower.empty() ? bound(k, i) : lower;
    if (o.total_labels) total_text[i] = plain(lower + label(totals[i]));
  }
  return {std::move(part_text), std::move(total_text)};
}

// Millimetres per world unit vertically and horizontally, and the character height, to decide
// which labels fit.
struct BarScale {
  double mm_per_y, mm_per_x, ht;
};

// The scale of the plot area PLplot has set up for n_cat bars up to y_hi.
BarScale bar_scale(double y_hi, size_t n_cat) {
  PLFLT sx0, sx1, sy0, sy1, vx0, vx1, vy0, vy1, def_ht, ht;
  plgspa(&sx0, &sx1, &sy0, &sy1);
  plgvpd(&vx0, &vx1, &vy0, &vy1);
  plgchr(&def_ht, &ht);
  const double mm_per_y = (vy1 - vy0) * (sy1 - sy0) / y_hi;
  const double mm_per_x = (vx1 - vx0) * (sx1 - sx0) / double(n_cat);
  return {mm_per_y, mm_per_x, ht};
}

// Stack k's part of bar i, from bottom to bottom + v, with its text inside when it fits.
void draw_bar_part(size_t i, size_t k, double bottom, double v, const std::string& text,
                   const BarScale& sc) {
  const double x0 = double(i) + 0.5 - kBarHalf, x1 = double(i) + 0.5 + kBarHalf;
  PLFLT rx[4] = {x0, x1, x1, x0}, ry[4] = {bottom, bottom, bottom + v, bottom + v};
  plcol0(PLINT(kFirstSeries + k));
  plfill(4, rx, ry);
  if (bottom > 0.0) {  // a white seam between parts
    plcol0(kWhite);
    pen(1.5);
    PLFLT ox[2] = {x0, x1}, oy[2] = {bottom, bottom};
    plline(2, ox, oy);
  }
  const double text_mm = 0.62 * sc.ht * double(text.size());
  if (!text.empty() && v * sc.mm_per_y > 1.9 * sc.ht &&
      text_mm < 2 * kBarHalf * sc.mm_per_x * 0.95) {
    const Colour c = plot_colour(k);
    const double luminance = (0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b) / 255.0;
    plcol0(luminance < 0.6 ? kWhite : kInk);
    plschr(0.0, 0.9);
    plptex(double(i) + 0.5, bottom + v / 2.0, 1.0, 0.0, 0.5, text.c_str());
    plschr(0.0, 1.0);
  }
}

// Bar i: its parts stacked from the first stack up, its total above it, its category below.
void draw_bar(size_t i, const std::vector<std::string>& categories,
              const std::vector<BarStack>& stacks, const std::vector<double>& totals,
              const BarTexts& texts, const BarScale& sc) {
  double bottom = 0.0;
  for (size_t k = 0; k < stacks.size(); ++k) {
    const double v = stacks[k].values[i];
    if (v <= 0.0) continue;
    draw_bar_part(i, k, bottom, v, texts.part[k][i], sc);
    bottom += v;
  }
  if (!texts.total[i].empty()) {
    plcol0(kInk);
    plptex(double(i) + 0.5, totals[i] + 1.1 * sc.ht / sc.mm_per_y, 1.0, 0.0, 0.5,
           texts.total[i].c_str());
  }
  plcol0(kInk);
  plschr(0.0, 1.05);
  plmtex("b", 1.4, (double(i) + 0.5) / double(categories.size()), 0.5,
         plain(categories[i]).c_str());
  plschr(0.0, 1.0);
}

// The legend: entries top to bottom in the order the parts are stacked, bottom part last.
void draw_bar_legend(const std::vector<BarStack>& stacks, LegendPosition position) {
  std::vector<std::string> legend_names;
  std::vector<PLINT> boxes, lines;
  for (size_t k = stacks.size(); k-- > 0;) {
    legend_names.push_back(stacks[k].name);
    boxes.push_back(PLINT(kFirstSeries + k));
    lines.push_back(PLINT(kFirstSeries + k));
  }
  draw_legend(legend_names, lines, boxes, false, position);
}

// How much of the bars lies in a box of the plot area (its fractions): the area the box shares
// with each bar and the label over its total (two character heights).
DataCover bar_cover(const std::vector<double>& totals, double y_hi) {
  return [&totals, y_hi](double x0, double x1, double y0, double y1) {
    const double n = double(totals.size()), label = 2.0 / viewport_chars().second;
    double covered = 0.0;
    for (size_t i = 0; i < totals.size(); ++i) {
      const double left = (double(i) + 0.5 - kBarHalf) / n, right = (double(i) + 0.5 + kBarHalf) / n;
      const double top = totals[i] / y_hi + label;
      covered += std::max(0.0, std::min(x1, right) - std::max(x0, left)) * std::max(0.0, std::min(y1, top) - y0);
    }
    return covered;
  };
}

}  // namespace

LegendPosition plot_stacked_bars(const std::string& path, const std::string& title,
                                 const std::vector<std::string>& categories,
                                 const std::vector<BarStack>& stacks, const BarOptions& options) {
  return plot_stacked_bars(std::vector<std::string>{path}, title, categories, stacks, options);
}

LegendPosition plot_stacked_bars(const std::vector<std::string>& paths, const std::string& title,
                       const std::vector<std::string>& categories,
                       const std::vector<BarStack>& stacks, const BarOptions& o) {
  check_bars(categories, stacks);
  for (const auto& p : paths) format_of(p);

  const size_t n_cat = categories.size(), n_stack = stacks.size();
  std::vector<double> totals(n_cat, 0.0);
  for (const auto& st : stacks)
    for (size_t i = 0; i < n_cat; ++i) totals[i] += st.values[i];
  const double top = *std::max_element(totals.begin(), totals.end());
  const double y_hi = top > 0.0 ? top * 1.12 : 1.0;

  // Labels are computed before PLplot starts, so a throwing value_label leaves PLplot untouched.
  const BarTexts texts = bar_texts(stacks, totals, o);

  std::vector<std::string> names;
  for (const auto& st : stacks) names.push_back(st.name);
  const PLINT colours = PLINT(kFirstSeries + n_stack);
  LegendPosition placed = o.legend;
  draw_figure(paths, o.width_px, o.height_px, colours, [&] {
    for (size_t k = 0; k < n_stack; ++k) {
      const Colour c = plot_colour(k);
      plscol0a(PLINT(kFirstSeries + k), c.r, c.g, c.b, 1.0);
    }
    const LegendPosition legend = placed =
        place_legend(o.legend, names, bar_cover(totals, y_hi),
                     {LegendPosition::kTopRight, LegendPosition::kTopLeft, LegendPosition::kBottomRight,
                      LegendPosition::kBottomLeft});
    plwind(0.0, double(n_cat), 0.0, y_hi);

    const double y_step = nice_step(y_hi, y_tick_target(viewport_chars().second));
    plcol0(kGrid);
    pen(1.0);
    plbox("", 0.0, 0, "g", y_step, 0);

    const BarScale sc = bar_scale(y_hi, n_cat);
    for (size_t i = 0; i < n_cat; ++i) draw_bar(i, categories, stacks, totals, texts, sc);

    draw_axes("", 0.0, y_step);
    draw_labels(title, "", o.y_label);
    draw_bar_legend(stacks, legend);
  });
  return placed;
}

}  // namespace roger
