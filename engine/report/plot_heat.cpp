// plot_heat.cpp: heat maps (see plot.h): a share in [0, 1] per cell of columns (bins of an x
// axis) and rows (labelled values), shaded from white to deep blue in ten steps with a key.
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

constexpr int kShades = 10;

// Throws unless the map has columns (increasing edges), rows, and a share in [0, 1] per cell.
void check_heat(const HeatMap& m) {
  if (m.x_edges.size() < 2) throw Error("plot: a heat map needs at least one column (two x edges)");
  check_finite(m.x_edges, "heat map x edges");
  for (size_t i = 1; i < m.x_edges.size(); ++i)
    if (!(m.x_edges[i] > m.x_edges[i - 1])) throw Error("plot: a heat map's x edges must increase");
  if (m.rows.empty()) throw Error("plot: a heat map needs at least one row");
  if (m.share.size() != m.rows.size()) throw Error("plot: a heat map needs one row of shares per row label");
  for (size_t r = 0; r < m.share.size(); ++r) {
    if (m.share[r].size() + 1 != m.x_edges.size())
      throw Error("plot: heat map row " + std::to_string(r) + " has " + std::to_string(m.share[r].size()) +
                  " shares for " + std::to_string(m.x_edges.size() - 1) + " columns");
    check_finite(m.share[r], "heat map row " + std::to_string(r) + " shares");
    for (double v : m.share[r])
      if (v < 0.0 || v > 1.0) throw Error("plot: a heat map's shares lie in [0, 1], got " + number(v));
  }
}

// The width of a row label's character in character heights (PLplot's height is about a capital's,
// and a digit is wider than 0.62 of it: at 0.62 the axis's title ran into a label "10").
constexpr double kLabelCharWidth = 0.85;

// Shade k of kShades: from nearly white to deep blue.
Colour shade(int k) {
  const double t = (k + 0.5) / kShades;
  return {uint8_t(247 - t * (247 - 8)), uint8_t(251 - t * (251 - 48)), uint8_t(255 - t * (255 - 107))};
}

}  // namespace

void plot_heat_map(const std::vector<std::string>& paths, const std::string& title, const HeatMap& m,
                   const HeatOptions& o) {
  check_heat(m);
  for (const auto& p : paths) format_of(p);
  std::vector<std::string> key;
  for (int k = kShades - 1; k >= 0; --k) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%d-%d%%", 100 * k / kShades, 100 * (k + 1) / kShades);
    key.push_back(buf);
  }
  const double right = right_margin(LegendPosition::kOutsideRight, key);
  size_t label = 0;
  for (const auto& r : m.rows) label = std::max(label, r.size());
  draw_figure(paths, o.width_px, o.height_px, PLINT(kFirstSeries + kShades), [&] {
    for (int k = 0; k < kShades; ++k) {
      const Colour c = shade(k);
      plscol0a(PLINT(kFirstSeries + k), c.r, c.g, c.b, 1.0);
    }
    set_viewport(right);
    {  // more room on the left for the rows' labels, written across
      PLFLT def_ht, ht, sx0, sx1, sy0, sy1, vx0, vx1, vy0, vy1;
      plgchr(&def_ht, &ht);
      plgspa(&sx0, &sx1, &sy0, &sy1);
      plgvpd(&vx0, &vx1, &vy0, &vy1);
      plvpor(std::min(0.45, (3.2 + kLabelCharWidth * double(label)) * ht / (sx1 - sx0)), vx1, vy0, vy1);
    }
    const double x0 = m.x_edges.front(), x1 = m.x_edges.back(), rows = double(m.rows.size());
    plwind(x0, x1, 0.0, rows);
    for (size_t r = 0; r < m.rows.size(); ++r)
      for (size_t c = 0; c + 1 < m.x_edges.size(); ++c) {
        const double v = m.share[r][c];
        if (v <= 0.0) continue;
        PLFLT rx[4] = {m.x_edges[c], m.x_edges[c + 1], m.x_edges[c + 1], m.x_edges[c]};
        PLFLT ry[4] = {double(r), double(r), double(r) + 1.0, double(r) + 1.0};
        plcol0(PLINT(kFirstSeries + std::min(kShades - 1, int(v * kShades))));
        plfill(4, rx, ry);
      }
    const double x_step = nice_step(x1 - x0, x_tick_target(viewport_chars().first, label_chars(x0, x1)));
    plcol0(kInk);
    pen(1.0);
    plbox("bcnt", x_step, 0, "bc", 0.0, 0);
    for (size_t r = 0; r < m.rows.size(); ++r)
      plmtex("lv", 0.6, (double(r) + 0.5) / rows, 1.0, plain(m.rows[r]).c_str());
    draw_labels(title, o.x_label, "");
    // Beyond the rows' labels (0.6 from the axis, kLabelCharWidth of a character's height per
    // character): a text written along the left edge stands on its baseline and rises a
    // character's height towards the axis, so its baseline is a height and a gap further out.
    plmtex("l", 2.0 + kLabelCharWidth * double(label), 0.5, 0.5, plain(o.y_label).c_str());
    std::vector<PLINT> boxes;
    for (int k = kShades - 1; k >= 0; --k) boxes.push_back(PLINT(kFirstSeries + k));
    draw_legend(key, boxes, boxes, false, LegendPosition::kOutsideRight);
  });
}

}  // namespace roger
