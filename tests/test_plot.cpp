// Tests of plot.h: figures load back as PNG at the promised size with the band and bar colours in
// them, SVGs are complete, files are written atomically, and bad input is a clear roger::Error
// that leaves no file behind.
#include <cairo.h>
#include <stdlib.h>
#include <unistd.h>

#include <catch2/catch.hpp>

#include "temp_dir.h"
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>
#include <vector>

#include "core/error.h"
#include "report/plot.h"
#include "report/plot_internal.h"
#include "report/stats.h"

namespace fs = std::filesystem;
using namespace roger;
using Catch::Matchers::Contains;

namespace {

// A scratch folder named after this test file.
struct TempDir : roger::test::TempDir {
  TempDir() : roger::test::TempDir("test_plot") {}
};

std::string read_all(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// A decoded PNG, owned.
struct Png {
  cairo_surface_t* surface = nullptr;
  explicit Png(const std::string& path) {
    surface = cairo_image_surface_create_from_png(path.c_str());
  }
  ~Png() { cairo_surface_destroy(surface); }
  bool ok() const { return cairo_surface_status(surface) == CAIRO_STATUS_SUCCESS; }
  int width() const { return cairo_image_surface_get_width(surface); }
  int height() const { return cairo_image_surface_get_height(surface); }
  // Pixels within `tolerance` of the colour in every channel, over the whole picture.
  long count(int r, int g, int b, int tolerance) const {
    cairo_surface_flush(surface);
    const unsigned char* data = cairo_image_surface_get_data(surface);
    const int stride = cairo_image_surface_get_stride(surface);
    long n = 0;
    for (int y = 0; y < height(); ++y)
      for (int x = 0; x < width(); ++x) {
        uint32_t px;
        std::memcpy(&px, data + y * stride + 4 * x, 4);
        const int pr = (px >> 16) & 0xff, pg = (px >> 8) & 0xff, pb = px & 0xff;
        if (std::abs(pr - r) <= tolerance && std::abs(pg - g) <= tolerance &&
            std::abs(pb - b) <= tolerance)
          ++n;
      }
    return n;
  }
  // Dark pixels (every channel under 160: text, not a band or a grid line) in [x0, x1) x [y0, y1).
  long ink(int x0, int x1, int y0, int y1) const {
    cairo_surface_flush(surface);
    const unsigned char* data = cairo_image_surface_get_data(surface);
    const int stride = cairo_image_surface_get_stride(surface);
    long n = 0;
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) {
        uint32_t px;
        std::memcpy(&px, data + y * stride + 4 * x, 4);
        n += ((px >> 16) & 0xff) < 160 && ((px >> 8) & 0xff) < 160 && (px & 0xff) < 160;
      }
    return n;
  }
};

bool has_png_signature(const std::string& path) {
  const std::string data = read_all(path);
  return data.size() > 8 && data.compare(0, 8, "\x89PNG\r\n\x1a\n", 8) == 0;
}

// One flat series: mean 0, std 50, over [0, 10] (so its band covers y in [-50, 50]).
std::vector<CurveSeries> flat_series() {
  CurveSeries c;
  c.name = "DC2";
  for (int i = 0; i <= 20; ++i) {
    c.x.push_back(0.5 * i);
    c.mean.push_back(0.0);
    c.std.push_back(50.0);
  }
  return {c};
}

// Three rising curves like Figure 3 (x in minutes, from 1).
std::vector<CurveSeries> figure3_series() {
  std::vector<CurveSeries> out;
  const char* names[] = {"B1", "DC1", "DC2"};
  const double half[] = {30.0, 25.0, 15.0};
  for (int k = 0; k < 3; ++k) {
    CurveSeries c;
    c.name = names[k];
    for (int i = 1; i <= 60; ++i) {
      const double p = 1.0 / (1.0 + std::exp(-(i - half[k]) / 4.0));
      c.x.push_back(i);
      c.mean.push_back(-100.0 + 200.0 * p);
      c.std.push_back(200.0 * std::sqrt(p * (1.0 - p)));
    }
    out.push_back(c);
  }
  return out;
}

std::vector<BarStack> figure5_stacks() {
  const double sg = 1495.0 / 60.0;
  return {{"SG", {0.0, sg, sg, sg, sg}}, {"T", {399.82, 333.17, 21.5, 16.5, 1.5}}};
}

const std::vector<std::string> kApproaches{"B2", "DC3", "DC4", "DC5", "DC6"};

// The colour of a band of opacity alpha over the white background.
int over_white(int channel, double alpha) {
  return int(std::lround(255.0 - alpha * (255.0 - channel)));
}

}  // namespace

TEST_CASE("learning curves: a PNG of the promised size with the band colour in it", "[plot]") {
  TempDir dir;
  const std::string png = dir.file("curves.png");
  CurveOptions options;
  options.width_px = 800;
  options.height_px = 500;
  plot_learning_curves(png, "Learning curves", flat_series(), options);

  REQUIRE(has_png_signature(png));
  Png image(png);
  REQUIRE(image.ok());
  CHECK(image.width() == 800);
  CHECK(image.height() == 500);
  const Colour c = plot_colour(0);
  const long band = image.count(over_white(c.r, options.band_alpha),
                                over_white(c.g, options.band_alpha),
                                over_white(c.b, options.band_alpha), 3);
  CHECK(band > 20000);  // a large part of the plot area
  CHECK(image.count(c.r, c.g, c.b, 10) > 300);  // the mean line
  CHECK(image.count(255, 255, 255, 0) > 50000);  // white background
  CHECK(dir.names() == std::vector<std::string>{"curves.png"});  // no temporary left

  // Without the std there is no band.
  std::vector<CurveSeries> bare = flat_series();
  bare[0].std.clear();
  plot_learning_curves(png, "", bare, options);
  Png plain(png);
  REQUIRE(plain.ok());
  CHECK(plain.count(over_white(c.r, 0.2), over_white(c.g, 0.2), over_white(c.b, 0.2), 3) < 100);
}

// Found by a probe: a title longer than the figure was centred and cropped at both ends.
TEST_CASE("a title too long for its figure is cut with an ellipsis, not cropped", "[plot]") {
  using plot_internal::fitted_title;
  CHECK(fitted_title("Learning curves: stage SG", 200.0, 5.0) == "Learning curves: stage SG");
  const std::string cut = fitted_title(std::string(200, 'x'), 85.0, 5.0);  // room for 19 characters
  CHECK(cut == std::string(18, 'x') + "\u2026");
  std::string accents;
  for (int k = 0; k < 40; ++k) accents += "\u00e9";  // two bytes each
  CHECK(fitted_title(accents, 85.0, 5.0) == accents.substr(0, 36) + "\u2026");  // whole characters

  TempDir dir;
  const std::string png = dir.file("long.png");
  CurveOptions options;
  options.width_px = 800;
  options.height_px = 500;
  std::string title = "Learning curves: stage ";
  for (int k = 0; k < 30; ++k) title += "long";
  plot_learning_curves(png, title, flat_series(), options);
  Png image(png);
  REQUIRE(image.ok());
  const int band = image.height() / 12;  // the title's rows, above the plot
  CHECK(image.ink(0, image.width(), 0, band) > 200);  // the title is drawn
  CHECK(image.ink(0, 6, 0, band) == 0);               // and ends inside the figure on either side
  CHECK(image.ink(image.width() - 6, image.width(), 0, band) == 0);
}

TEST_CASE("learning curves: SVG, and PNG plus SVG from one call", "[plot]") {
  TempDir dir;
  const std::string svg = dir.file("figure3.svg");
  plot_learning_curves(svg, "Phi_SG # learning", figure3_series());
  const std::string text = read_all(svg);
  CHECK(text.find("<svg") != std::string::npos);
  CHECK(text.find("</svg>") != std::string::npos);

  const std::vector<std::string> both{dir.file("fig3.png"), dir.file("FIG3.SVG")};
  plot_learning_curves(both, "Figure 3", figure3_series());
  CHECK(has_png_signature(both[0]));
  CHECK(read_all(both[1]).find("<svg") != std::string::npos);
  CHECK(dir.names().size() == 3);
}

TEST_CASE("learning curves: log x over whole decades, and non-positive x is an error", "[plot]") {
  TempDir dir;
  CurveOptions log_x;
  log_x.log_x = true;
  std::vector<CurveSeries> series = figure3_series();
  plot_learning_curves(dir.file("log.png"), "Figure 4", series, log_x);
  Png image(dir.file("log.png"));
  REQUIRE(image.ok());
  CHECK(image.width() == log_x.width_px);

  series[1].x.front() = 0.0;
  CHECK_THROWS_AS(plot_learning_curves(dir.file("bad.png"), "", series, log_x), Error);
  CHECK_THROWS_WITH(plot_learning_curves(dir.file("bad.png"), "", series, log_x),
                    Contains("series 1 ('DC1') x[0] is 0") && Contains("log"));
  series[1].x.front() = -3.0;
  CHECK_THROWS_WITH(plot_learning_curves(dir.file("bad.svg"), "", series, log_x),
                    Contains("x > 0"));
  // The same data is fine on a linear axis.
  series[1].x.front() = 0.0;
  plot_learning_curves(dir.file("linear.png"), "", series);
  CHECK(dir.names().size() == 2);  // log.png and linear.png, nothing else
}

TEST_CASE("learning curves: an asymmetric low..high band is drawn where its bounds say", "[plot]") {
  TempDir dir;
  const std::string png = dir.file("iqm.png");
  // An IQM-like series: the line at 0, its band from 20 to 80, wholly above the line.
  std::vector<CurveSeries> s = flat_series();
  s[0].std.clear();
  s[0].low.assign(s[0].x.size(), 20.0);
  s[0].high.assign(s[0].x.size(), 80.0);
  CurveOptions o;
  o.fit_data = false;
  plot_learning_curves(png, "IQM", s, o);
  Png image(png);
  REQUIRE(image.ok());
  const Colour c = plot_colour(0);
  const int br = over_white(c.r, o.band_alpha), bg = over_white(c.g, o.band_alpha),
            bb = over_white(c.b, o.band_alpha);
  CHECK(image.count(br, bg, bb, 3) > 10000);
  // In the middle column, every band pixel lies above (a smaller row than) every line pixel.
  cairo_surface_flush(image.surface);
  const unsigned char* data = cairo_image_surface_get_data(image.surface);
  const int stride = cairo_image_surface_get_stride(image.surface);
  const int x = image.width() / 2;
  int band_lowest = -1, line_highest = image.height(), band_rows = 0;
  for (int y = 0; y < image.height(); ++y) {
    uint32_t px;
    std::memcpy(&px, data + y * stride + 4 * x, 4);
    const int r = (px >> 16) & 0xff, g = (px >> 8) & 0xff, b = px & 0xff;
    if (std::abs(r - br) <= 3 && std::abs(g - bg) <= 3 && std::abs(b - bb) <= 3)
      band_lowest = std::max(band_lowest, y), ++band_rows;
    if (std::abs(r - c.r) <= 10 && std::abs(g - c.g) <= 10 && std::abs(b - c.b) <= 10)
      line_highest = std::min(line_highest, y);
  }
  REQUIRE(band_rows > 0);
  REQUIRE(line_highest < image.height());
  CHECK(band_lowest < line_highest);
  // The band spans 60 of the 200 (+12% margin) units of the y axis: about that share of the
  // plot area's height, not the 100 units of a mean +- 50 band.
  const double share = double(band_rows) / double(image.height());
  CHECK(share > 0.15);
  CHECK(share < 0.3);

  // Bad bands are clear errors: both kinds at once, a missing bound, bounds out of order.
  std::vector<CurveSeries> bad = s;
  bad[0].std.assign(bad[0].x.size(), 1.0);
  CHECK_THROWS_WITH(plot_learning_curves(png, "", bad), Contains("one or the other"));
  bad = s;
  bad[0].high.pop_back();
  CHECK_THROWS_WITH(plot_learning_curves(png, "", bad), Contains("20 band highs"));
  bad = s;
  bad[0].low[7] = 90.0;
  CHECK_THROWS_WITH(plot_learning_curves(png, "", bad), Contains("low[7] = 90 is above high[7] = 80"));
  bad = s;
  bad[0].low[3] = std::nan("");
  CHECK_THROWS_AS(plot_learning_curves(png, "", bad), Error);
}

TEST_CASE("learning curves: bad input is a clear error", "[plot]") {
  TempDir dir;
  const std::string png = dir.file("x.png");
  std::vector<CurveSeries> s = flat_series();
  CHECK_THROWS_WITH(plot_learning_curves(png, "", {}), Contains("at least one series"));
  s[0].mean.pop_back();
  CHECK_THROWS_WITH(plot_learning_curves(png, "", s), Contains("21 x values but 20 means"));
  s = flat_series();
  s[0].std.resize(3);
  CHECK_THROWS_WITH(plot_learning_curves(png, "", s), Contains("standard deviations"));
  s = flat_series();
  s[0].mean[4] = std::nan("");
  CHECK_THROWS_WITH(plot_learning_curves(png, "", s), Contains("mean[4]"));
  s = flat_series();
  s[0].std[2] = -1.0;
  CHECK_THROWS_WITH(plot_learning_curves(png, "", s), Contains(">= 0"));
  s = flat_series();
  std::swap(s[0].x[3], s[0].x[4]);
  CHECK_THROWS_WITH(plot_learning_curves(png, "", s), Contains("increasing"));
  CurveOptions o;
  o.y_min = 5;
  o.y_max = 5;
  CHECK_THROWS_WITH(plot_learning_curves(png, "", flat_series(), o), Contains("y range"));
  o = CurveOptions();
  o.width_px = 10;
  CHECK_THROWS_WITH(plot_learning_curves(png, "", flat_series(), o), Contains("pixels"));
  o = CurveOptions();
  o.band_alpha = 1.5;
  CHECK_THROWS_AS(plot_learning_curves(png, "", flat_series(), o), Error);
  CHECK(dir.names().empty());
}

TEST_CASE("a bad extension or an unwritable folder is an error and leaves no file", "[plot]") {
  TempDir dir;
  CHECK_THROWS_WITH(plot_learning_curves(dir.file("fig.jpg"), "", flat_series()),
                    Contains("unknown extension '.jpg'") && Contains(".png or .svg"));
  CHECK_THROWS_WITH(plot_learning_curves(dir.file("fig"), "", flat_series()),
                    Contains("no extension"));
  CHECK_THROWS_WITH(plot_stacked_bars(dir.file("bars.pdf"), "", kApproaches, figure5_stacks()),
                    Contains("'.pdf'"));
  // A missing folder, and a "folder" that is a regular file.
  CHECK_THROWS_WITH(plot_learning_curves(dir.file("missing/fig.png"), "", flat_series()),
                    Contains("missing/fig.png") && Contains("No such file or directory"));
  std::ofstream(dir.file("plain.txt")) << "not a folder";
  CHECK_THROWS_WITH(plot_stacked_bars(dir.file("plain.txt/fig.svg"), "", kApproaches,
                                      figure5_stacks()),
                    Contains("Not a directory"));
  // A folder without write permission (root ignores permissions, so only checked for others).
  if (geteuid() != 0) {
    const fs::path locked = dir.path / "locked";
    fs::create_directory(locked);
    fs::permissions(locked, fs::perms::owner_read | fs::perms::owner_exec);
    CHECK_THROWS_WITH(plot_learning_curves((locked / "fig.png").string(), "", flat_series()),
                      Contains("Permission denied"));
    CHECK(fs::is_empty(locked));
    fs::permissions(locked, fs::perms::owner_all);
    fs::remove(locked);
  }
  // One bad path among several: nothing is written, not even the good one.
  const std::vector<std::string> mixed{dir.file("good.png"), dir.file("bad.gif")};
  CHECK_THROWS_AS(plot_learning_curves(mixed, "", flat_series()), Error);
  const std::vector<std::string> unreachable{dir.file("good.png"), dir.file("no/such.svg")};
  CHECK_THROWS_AS(plot_learning_curves(unreachable, "", flat_series()), Error);
  CHECK(dir.names() == std::vector<std::string>{"plain.txt"});
  CHECK_THROWS_AS(plot_learning_curves(std::vector<std::string>{}, "", flat_series()), Error);
}

TEST_CASE("a legend beside the plot, and a figure too narrow to hold it", "[plot]") {
  TempDir dir;
  CurveOptions options;
  options.legend = LegendPosition::kOutsideRight;
  plot_learning_curves(dir.file("outside.png"), "Figure 4", figure3_series(), options);
  Png image(dir.file("outside.png"));
  REQUIRE(image.ok());
  CHECK(image.width() == 1000);

  // Found only once PLplot is drawing: the session is closed and the temporary removed.
  std::vector<CurveSeries> long_names = figure3_series();
  long_names[0].name = std::string(60, 'x');
  options.width_px = 400;
  CHECK_THROWS_WITH(plot_learning_curves(dir.file("narrow.png"), "", long_names, options),
                    Contains("too narrow"));
  CHECK(dir.names() == std::vector<std::string>{"outside.png"});
  plot_learning_curves(dir.file("after.svg"), "", long_names);
  CHECK(read_all(dir.file("after.svg")).find("</svg>") != std::string::npos);
}

// Found by a probe: the legend sat in a fixed corner, over the curves of a context that never
// learned and over the tallest bar. By default it takes the corner the data leaves free.
TEST_CASE("a legend goes where the data is not, or beside the plot", "[plot]") {
  TempDir dir;
  const std::string png = dir.file("legend.png");
  CHECK(plot_learning_curves(png, "", figure3_series()) == LegendPosition::kBottomRight);  // rising curves
  auto flat_at = [](double y, const char* name) {
    CurveSeries c;
    c.name = name;
    for (int i = 0; i <= 40; ++i) {
      c.x.push_back(i);
      c.mean.push_back(y);
      c.std.push_back(2.0);
    }
    return c;
  };
  // A context that never learned lies along the bottom: the top left is free.
  CHECK(plot_learning_curves(png, "", {flat_at(-100, "B1")}) == LegendPosition::kTopLeft);
  // One along the bottom and one along the top: every corner holds a curve.
  CHECK(plot_learning_curves(png, "", {flat_at(-100, "B1"), flat_at(100, "DC2")}) == LegendPosition::kOutsideRight);
  CurveOptions fixed;
  fixed.legend = LegendPosition::kBottomRight;  // asked for: kept, over the data or not
  CHECK(plot_learning_curves(png, "", {flat_at(-100, "B1")}, fixed) == LegendPosition::kBottomRight);
  // Too narrow for a legend beside the plot: the corner that hides the least.
  CurveOptions narrow;
  narrow.width_px = 400;
  CHECK(plot_learning_curves(png, "", {flat_at(-100, std::string(60, 'x').c_str()), flat_at(100, "DC2")}, narrow) !=
        LegendPosition::kOutsideRight);
  // Bars: the tall one on the right leaves the top left free.
  const std::vector<BarStack> stacks{{"SG", {1.0, 8.0}, {}}, {"T", {1.0, 10.0}, {}}};
  CHECK(plot_stacked_bars(png, "", {"B2", "DC6"}, stacks) == LegendPosition::kTopLeft);
  const std::vector<BarStack> left_tall{{"SG", {8.0, 1.0}, {}}, {"T", {10.0, 1.0}, {}}};
  CHECK(plot_stacked_bars(png, "", {"B2", "DC6"}, left_tall) == LegendPosition::kTopRight);
}

TEST_CASE("a figure replaces an old file whole, and a failure keeps the old one", "[plot]") {
  TempDir dir;
  const std::string png = dir.file("fig.png");
  std::ofstream(png) << "old content";
  plot_learning_curves(png, "new", flat_series());
  CHECK(has_png_signature(png));
  const std::string before = read_all(png);
  std::vector<CurveSeries> bad = flat_series();
  bad[0].x.clear();
  CHECK_THROWS_AS(plot_learning_curves(png, "", bad), Error);
  CHECK(read_all(png) == before);
  CHECK(dir.names() == std::vector<std::string>{"fig.png"});
}

TEST_CASE("stacked bars: PNG with both parts' colours, and SVG", "[plot]") {
  TempDir dir;
  BarOptions options;
  options.value_label = [](double minutes) { return format_min_sec(60.0 * minutes); };
  options.width_px = 900;
  options.height_px = 600;
  const std::vector<std::string> paths{dir.file("fig5.png"), dir.file("fig5.svg")};
  plot_stacked_bars(paths, "Cumulative training time", kApproaches, figure5_stacks(), options);

  REQUIRE(has_png_signature(paths[0]));
  Png image(paths[0]);
  REQUIRE(image.ok());
  CHECK(image.width() == 900);
  CHECK(image.height() == 600);
  const Colour sg = plot_colour(0), t = plot_colour(1);
  CHECK(image.count(sg.r, sg.g, sg.b, 2) > 2000);
  CHECK(image.count(t.r, t.g, t.b, 2) > 20000);
  const std::string svg = read_all(paths[1]);
  CHECK(svg.find("<svg") != std::string::npos);
  CHECK(dir.names().size() == 2);

  // Zero everywhere still draws (an empty chart with its axes).
  const std::vector<BarStack> zeros{{"SG", {0, 0}}, {"T", {0, 0}}};
  plot_stacked_bars(dir.file("zeros.png"), "", {"A", "B"}, zeros);
  CHECK(has_png_signature(dir.file("zeros.png")));
}

TEST_CASE("stacked bars: bad input is a clear error", "[plot]") {
  TempDir dir;
  const std::string png = dir.file("bars.png");
  CHECK_THROWS_WITH(plot_stacked_bars(png, "", {}, figure5_stacks()),
                    Contains("at least one category"));
  CHECK_THROWS_WITH(plot_stacked_bars(png, "", kApproaches, {}), Contains("at least one stack"));
  std::vector<BarStack> stacks = figure5_stacks();
  stacks[1].values.pop_back();
  CHECK_THROWS_WITH(plot_stacked_bars(png, "", kApproaches, stacks),
                    Contains("stack 1 ('T') has 4 values for 5 categories"));
  stacks = figure5_stacks();
  stacks[0].values[2] = -1.0;
  CHECK_THROWS_WITH(plot_stacked_bars(png, "", kApproaches, stacks), Contains(">= 0"));
  stacks = figure5_stacks();
  stacks[0].values[2] = INFINITY;
  CHECK_THROWS_WITH(plot_stacked_bars(png, "", kApproaches, stacks), Contains("finite"));
  // A value label that throws stops the figure before anything is written.
  BarOptions throwing;
  throwing.value_label = [](double v) { return format_min_sec(-v - 1.0); };
  CHECK_THROWS_WITH(plot_stacked_bars(png, "", kApproaches, figure5_stacks(), throwing),
                    Contains("not a duration"));
  CHECK(dir.names().empty());
  // PLplot is still usable after all these errors.
  plot_stacked_bars(png, "", kApproaches, figure5_stacks());
  CHECK(has_png_signature(png));
}

TEST_CASE("figures from several threads at once are all whole", "[plot]") {
  TempDir dir;
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t)
    threads.emplace_back([&dir, t] {
      for (int i = 0; i < 2; ++i) {
        const std::string stem = "t" + std::to_string(t) + "_" + std::to_string(i);
        if ((t + i) % 2 == 0)
          plot_learning_curves(dir.file(stem + ".png"), stem, figure3_series());
        else
          plot_stacked_bars(dir.file(stem + ".png"), stem, kApproaches, figure5_stacks());
      }
    });
  for (auto& th : threads) th.join();
  CHECK(dir.names().size() == 8);
  for (const auto& name : dir.names()) {
    Png image(dir.file(name));
    CHECK(image.ok());
    CHECK(image.width() == 1000);
  }
}
