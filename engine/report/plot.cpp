// plot.cpp: see plot.h. Every PLplot call happens under g_plplot_mutex, between one plinit and
// one plend, on a device and output file chosen per figure.
#include "report/plot.h"

#include <fcntl.h>
#include <plplot.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <mutex>
#include <random>
#include <sstream>

#include "core/error.h"

namespace roger {
namespace {

namespace fs = std::filesystem;

std::mutex g_plplot_mutex;

// Thrown by PLplot's exit hook (plexit) instead of letting PLplot call exit().
struct PlplotFailure : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The first non-fatal PLplot error (plabort) of the figure being drawn; guarded by the mutex.
std::string g_plplot_abort;

int on_plplot_exit(const char* message) {
  throw PlplotFailure(message && *message ? message : "unknown PLplot error");
}

void on_plplot_abort(const char* message) {
  if (g_plplot_abort.empty()) g_plplot_abort = message && *message ? message : "unknown error";
}

enum class Format { kPng, kSvg };

// The format named by path's extension, or an Error naming the two accepted ones.
Format format_of(const std::string& path) {
  const std::string ext = fs::path(path).extension().string();
  std::string lower = ext;
  for (char& c : lower) c = char(std::tolower(static_cast<unsigned char>(c)));
  if (lower == ".png") return Format::kPng;
  if (lower == ".svg") return Format::kSvg;
  const std::string why =
      ext.empty() ? std::string("it has no extension") : "unknown extension '" + ext + "'";
  throw Error("plot: cannot write figure '" + path + "': " + why + "; use .png or .svg");
}

// A temporary file beside the destination for PLplot to write; removed unless committed.
class TempFigure {
 public:
  TempFigure(const std::string& path, Format format) : path_(path), format_(format) {
    const fs::path target(path);
    if (target.filename().empty() || target.filename() == "." || target.filename() == "..")
      throw Error("plot: cannot write figure '" + path + "': it names a folder, not a file");
    const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
    // PLplot treats "%n" in a file name as a family member number: keep it out of the name.
    if (dir.string().find("%n") != std::string::npos)
      throw Error("plot: cannot write figure '" + path + "': PLplot cannot write into a folder "
                  "whose name contains '%n'");
    static std::atomic<unsigned> counter{0};
    std::random_device rd;
    for (int attempt = 0; attempt < 100; ++attempt) {
      const std::string name = ".roger-plot-" + std::to_string(getpid()) + "-" +
                               std::to_string(counter++) + "-" + std::to_string(rd() % 100000) +
                               ".tmp";
      temp_ = (dir / name).string();
      // 0666 and O_EXCL: the umask decides the final permissions, and no other file is clobbered.
      const int fd = ::open(temp_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
      if (fd >= 0) {
        ::close(fd);
        return;
      }
      if (errno != EEXIST) {
        const int err = errno;
        temp_.clear();
        fail(std::strerror(err));
      }
    }
    temp_.clear();
    fail(std::strerror(EEXIST));
  }
  ~TempFigure() {
    if (!committed_ && !temp_.empty()) ::unlink(temp_.c_str());
  }
  TempFigure(const TempFigure&) = delete;
  TempFigure& operator=(const TempFigure&) = delete;

  const std::string& temp() const { return temp_; }
  const std::string& path() const { return path_; }
  Format format() const { return format_; }

  // Checks that PLplot wrote a whole PNG or SVG, and flushes it to disk.
  void verify() {
    std::ifstream in(temp_, std::ios::binary);
    const std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (!in.good() && !in.eof()) fail("cannot read back what PLplot wrote");
    bool whole = false;
    if (format_ == Format::kPng) {
      static const char kSignature[] = "\x89PNG\r\n\x1a\n";
      static const char kEnd[] = "IEND\xae\x42\x60\x82";
      whole = data.size() > 20 && data.compare(0, 8, kSignature, 8) == 0 &&
              data.compare(data.size() - 8, 8, kEnd, 8) == 0;
    } else {
      const size_t close = data.rfind("</svg>");
      whole = data.find("<svg") != std::string::npos && close != std::string::npos &&
              data.find_first_not_of(" \t\r\n", close + 6) == std::string::npos;
    }
    if (!whole)
      fail("PLplot wrote an incomplete " + std::string(format_ == Format::kPng ? "PNG" : "SVG") +
           " (" + std::to_string(data.size()) + " bytes): is the disk full?");
    const int fd = ::open(temp_.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0 || ::fsync(fd) != 0) {
      const int err = errno;
      if (fd >= 0) ::close(fd);
      fail(std::strerror(err));
    }
    ::close(fd);
  }

  // Renames the verified temporary over the destination.
  void commit() {
    if (std::rename(temp_.c_str(), path_.c_str()) != 0) fail(std::strerror(errno));
    committed_ = true;
  }

 private:
  [[noreturn]] void fail(const std::string& why) const {
    throw Error("plot: cannot write figure '" + path_ + "': " + why);
  }

  std::string path_, temp_;
  Format format_;
  bool committed_ = false;
};

// Palette: colour-blind-safe (Okabe & Ito), cycled.
const Colour kPalette[] = {{0, 114, 178},   {213, 94, 0},   {0, 158, 115}, {204, 121, 167},
                           {230, 159, 0},   {86, 180, 233}, {90, 90, 90}};
constexpr size_t kPaletteSize = sizeof(kPalette) / sizeof(kPalette[0]);

// Line style of the index-th series: solid, then dashed patterns once the palette repeats.
PLINT line_style(size_t index) { return PLINT(1 + (index / kPaletteSize) % 8); }

// Fixed cmap0 entries; series colours follow from kFirstSeries.
enum : PLINT { kBackground = 0, kInk = 1, kGrid = 2, kFrame = 3, kWhite = 4, kFirstSeries = 5 };

// PLplot text with its escape character doubled, so '#' in a name is printed as itself.
std::string plain(const std::string& text) {
  std::string out;
  for (char c : text) {
    out += c;
    if (c == '#') out += '#';
  }
  return out;
}

// Owns one PLplot session from plinit to plend, with the hooks pointed at this figure.
class Session {
 public:
  Session(Format format, const std::string& file, int width, int height, PLINT colours) {
    g_plplot_abort.clear();
    plsexit(on_plplot_exit);
    plsabort(on_plplot_abort);
    plsdev(format == Format::kPng ? "pngcairo" : "svgcairo");
    plsfnam(file.c_str());
    plspage(0.0, 0.0, width, height, 0, 0);
    plscmap0n(colours);
    plscol0a(kBackground, 255, 255, 255, 1.0);
    plscol0a(kInk, 34, 34, 34, 1.0);
    plscol0a(kGrid, 222, 222, 222, 1.0);
    plscol0a(kFrame, 200, 200, 200, 1.0);
    plscol0a(kWhite, 255, 255, 255, 1.0);
    plsfont(PL_FCI_SANS, PL_FCI_UPRIGHT, PL_FCI_MEDIUM);
    try {
      plinit();
    } catch (const PlplotFailure&) {
      try {
        plend();  // release what plinit set up before it failed
      } catch (const PlplotFailure&) {
        // Reporting the first failure.
      }
      throw;
    }
    open_ = true;
    pladv(0);
    plschr(0.0, 1.0);
  }

  // Ends the session (the device writes its file) and reports any PLplot error on the way.
  void finish() {
    open_ = false;
    plend();
    if (!g_plplot_abort.empty()) throw PlplotFailure(g_plplot_abort);
  }

  ~Session() {
    if (!open_) return;
    try {
      plend();
    } catch (const PlplotFailure&) {
      // PLplot failed while cleaning up after another failure; the first one is being reported.
    }
  }
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

 private:
  bool open_ = false;
};

// Restores PLplot's default hooks when a figure is done, however it ends.
struct HookReset {
  ~HookReset() {
    plsexit(nullptr);
    plsabort(nullptr);
  }
};

// Throws unless PLplot's cairo devices are installed.
void check_devices() {
  static const int kMax = 256;
  const char* menu_storage[kMax];
  const char* name_storage[kMax];
  const char** menu = menu_storage;
  const char** names = name_storage;
  int n = kMax;  // in: room in the arrays; out: the number of devices
  plgDevs(&menu, &names, &n);
  bool png = false, svg = false;
  for (int i = 0; i < n && i < kMax; ++i) {
    png = png || std::strcmp(names[i], "pngcairo") == 0;
    svg = svg || std::strcmp(names[i], "svgcairo") == 0;
  }
  if (!png || !svg)
    throw Error(
        "plot: PLplot's cairo driver (devices pngcairo and svgcairo) is not installed; install "
        "the Debian package plplot-driver-cairo");
}

void check_size(int width, int height) {
  if (width < 200 || width > 8000 || height < 150 || height > 8000)
    throw Error("plot: a figure must be 200 to 8000 pixels wide and 150 to 8000 high, got " +
                std::to_string(width) + " x " + std::to_string(height));
}

// Draws the figure once per path (each into a checked temporary), then renames them all.
void draw_figure(const std::vector<std::string>& paths, int width, int height, PLINT colours,
                 const std::function<void()>& draw) {
  if (paths.empty()) throw Error("plot: no file to write the figure to");
  std::vector<Format> formats;
  for (const auto& p : paths) formats.push_back(format_of(p));
  check_size(width, height);

  std::lock_guard<std::mutex> lock(g_plplot_mutex);
  HookReset reset;
  plsexit(on_plplot_exit);
  check_devices();
  std::vector<std::unique_ptr<TempFigure>> temps;
  for (size_t i = 0; i < paths.size(); ++i)
    temps.push_back(std::make_unique<TempFigure>(paths[i], formats[i]));
  for (auto& temp : temps) {
    try {
      Session session(temp->format(), temp->temp(), width, height, colours);
      draw();
      session.finish();
    } catch (const PlplotFailure& e) {
      throw Error("plot: cannot write figure '" + temp->path() + "': PLplot: " + e.what());
    }
    temp->verify();
  }
  for (auto& temp : temps) temp->commit();
}

std::string number(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

// Throws unless every value is finite; `what` names the values for the message.
void check_finite(const std::vector<double>& values, const std::string& what) {
  for (size_t i = 0; i < values.size(); ++i)
    if (!std::isfinite(values[i]))
      throw Error("plot: " + what + "[" + std::to_string(i) + "] is " + number(values[i]) +
                  ", expected a finite number");
}

// PLplot's character height in millimetres on a 1000 x 650 page, where widths were tuned.
constexpr double kReferenceCharHeight = 5.82;

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

// The legend's PLplot position flags.
PLINT legend_position(LegendPosition p) {
  constexpr PLINT kIn = PL_POSITION_INSIDE;
  switch (p) {
    case LegendPosition::kBottomLeft: return kIn | PL_POSITION_BOTTOM | PL_POSITION_LEFT;
    case LegendPosition::kTopRight: return kIn | PL_POSITION_TOP | PL_POSITION_RIGHT;
    case LegendPosition::kTopLeft: return kIn | PL_POSITION_TOP | PL_POSITION_LEFT;
    case LegendPosition::kOutsideRight: return PL_POSITION_OUTSIDE | PL_POSITION_RIGHT;
    case LegendPosition::kBottomRight: break;
  }
  return kIn | PL_POSITION_BOTTOM | PL_POSITION_RIGHT;
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

// Title above the plot area and the two axis labels.
void draw_labels(const std::string& title, const std::string& x_label, const std::string& y_label) {
  plcol0(kInk);
  plschr(0.0, 1.05);
  plmtex("b", 3.0, 0.5, 0.5, plain(x_label).c_str());
  plmtex("l", 4.2, 0.5, 0.5, plain(y_label).c_str());
  if (!title.empty()) {
    plsfont(PL_FCI_SANS, PL_FCI_UPRIGHT, PL_FCI_BOLD);
    plschr(0.0, 1.3);
    plmtex("t", 1.6, 0.5, 0.5, plain(title).c_str());
    plsfont(PL_FCI_SANS, PL_FCI_UPRIGHT, PL_FCI_MEDIUM);
  }
  plschr(0.0, 1.0);
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

}  // namespace

Colour plot_colour(size_t index) { return kPalette[index % kPaletteSize]; }

void plot_learning_curves(const std::string& path, const std::string& title,
                          const std::vector<CurveSeries>& series, const CurveOptions& options) {
  plot_learning_curves(std::vector<std::string>{path}, title, series, options);
}

void plot_learning_curves(const std::vector<std::string>& paths, const std::string& title,
                          const std::vector<CurveSeries>& series, const CurveOptions& o) {
  check_series(series, o);
  for (const auto& p : paths) format_of(p);

  // World window: x over the data (whole decades on a log axis), y over the asked range.
  double x_lo = series[0].x.front(), x_hi = series[0].x.back();
  double y_lo = o.y_min, y_hi = o.y_max;
  for (const auto& c : series) {
    x_lo = std::min(x_lo, c.x.front());
    x_hi = std::max(x_hi, c.x.back());
    if (!o.fit_data) continue;
    for (size_t i = 0; i < c.x.size(); ++i) {
      const double s = c.std.empty() ? 0.0 : c.std[i];
      y_lo = std::min(y_lo, c.mean[i] - s);
      y_hi = std::max(y_hi, c.mean[i] + s);
    }
  }
  const auto tx = [&](double x) { return o.log_x ? std::log10(x) : x; };
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

  const size_t n = series.size();
  std::vector<std::string> names;
  for (const auto& c : series) names.push_back(c.name);
  const double right = right_margin(o.legend, names);
  const PLINT colours = PLINT(kFirstSeries + 2 * n);
  const auto line_index = [&](size_t s) { return PLINT(kFirstSeries + s); };
  const auto band_index = [&](size_t s) { return PLINT(kFirstSeries + n + s); };

  draw_figure(paths, o.width_px, o.height_px, colours, [&] {
    for (size_t s = 0; s < n; ++s) {
      const Colour c = plot_colour(s);
      plscol0a(line_index(s), c.r, c.g, c.b, 1.0);
      plscol0a(band_index(s), c.r, c.g, c.b, o.band_alpha);
    }
    set_viewport(right);
    plwind(x_lo, x_hi, y_lo, y_hi);
    const std::string x_axis = o.log_x ? "l" : "";

    const auto chars = viewport_chars();
    const double x_step =
        o.log_x ? 0.0 : nice_step(x_hi - x_lo, x_tick_target(chars.first, label_chars(x_lo, x_hi)));
    const double y_step = nice_step(y_hi - y_lo, y_tick_target(chars.second));
    plcol0(kGrid);
    pen(1.0);
    plbox(("g" + x_axis).c_str(), x_step, 0, "g", y_step, 0);

    for (size_t s = 0; s < n; ++s) {
      const CurveSeries& c = series[s];
      if (c.std.empty() || o.band_alpha == 0.0) continue;
      std::vector<PLFLT> bx, by;
      for (size_t i = 0; i < c.x.size(); ++i) {
        bx.push_back(tx(c.x[i]));
        by.push_back(c.mean[i] + c.std[i]);
      }
      for (size_t i = c.x.size(); i-- > 0;) {
        bx.push_back(tx(c.x[i]));
        by.push_back(c.mean[i] - c.std[i]);
      }
      plcol0(band_index(s));
      if (bx.size() >= 3) plfill(PLINT(bx.size()), bx.data(), by.data());
    }

    pen(2.2);
    for (size_t s = 0; s < n; ++s) {
      const CurveSeries& c = series[s];
      std::vector<PLFLT> lx, ly(c.mean.begin(), c.mean.end());
      for (double x : c.x) lx.push_back(tx(x));
      plcol0(line_index(s));
      pllsty(line_style(s));
      if (lx.size() > 1) {
        plline(PLINT(lx.size()), lx.data(), ly.data());
        continue;
      }
      // A single point: a dot with a +- std error bar instead of a line and a band.
      if (!c.std.empty()) {
        PLFLT lo = c.mean[0] - c.std[0], hi = c.mean[0] + c.std[0];
        plerry(1, lx.data(), &lo, &hi);
      }
      plstring(1, lx.data(), ly.data(), "\u25CF");
    }
    pllsty(1);

    draw_axes("nst" + x_axis, x_step, y_step);
    draw_labels(title, o.x_label, o.y_label);

    std::vector<PLINT> lines, boxes;
    for (size_t s = 0; s < n; ++s) {
      lines.push_back(line_index(s));
      boxes.push_back(series[s].std.empty() ? kBackground : band_index(s));
    }
    draw_legend(names, lines, boxes, true, o.legend);
  });
}

void plot_stacked_bars(const std::string& path, const std::string& title,
                       const std::vector<std::string>& categories,
                       const std::vector<BarStack>& stacks, const BarOptions& options) {
  plot_stacked_bars(std::vector<std::string>{path}, title, categories, stacks, options);
}

void plot_stacked_bars(const std::vector<std::string>& paths, const std::string& title,
                       const std::vector<std::string>& categories,
                       const std::vector<BarStack>& stacks, const BarOptions& o) {
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
  for (const auto& p : paths) format_of(p);

  const size_t n_cat = categories.size(), n_stack = stacks.size();
  std::vector<double> totals(n_cat, 0.0);
  for (const auto& st : stacks)
    for (size_t i = 0; i < n_cat; ++i) totals[i] += st.values[i];
  const double top = *std::max_element(totals.begin(), totals.end());
  const double y_hi = top > 0.0 ? top * 1.12 : 1.0;

  const auto label = [&](double v) {
    if (o.value_label) return o.value_label(v);
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.4g", v);
    return std::string(buf);
  };
  // Labels are computed before PLplot starts, so a throwing value_label leaves PLplot untouched.
  std::vector<std::vector<std::string>> part_text(n_stack, std::vector<std::string>(n_cat));
  std::vector<std::string> total_text(n_cat);
  for (size_t i = 0; i < n_cat; ++i) {
    size_t parts = 0;
    for (const auto& st : stacks) parts += st.values[i] > 0.0 ? 1 : 0;
    // A bar of one part has its value above it already when totals are labelled.
    if (!o.part_labels || (parts == 1 && o.total_labels)) continue;
    for (size_t k = 0; k < n_stack; ++k) part_text[k][i] = plain(label(stacks[k].values[i]));
  }
  for (size_t i = 0; i < n_cat; ++i)
    if (o.total_labels) total_text[i] = plain(label(totals[i]));

  std::vector<std::string> names;
  for (const auto& st : stacks) names.push_back(st.name);
  const double right = right_margin(o.legend, names);
  const PLINT colours = PLINT(kFirstSeries + n_stack);
  draw_figure(paths, o.width_px, o.height_px, colours, [&] {
    for (size_t k = 0; k < n_stack; ++k) {
      const Colour c = plot_colour(k);
      plscol0a(PLINT(kFirstSeries + k), c.r, c.g, c.b, 1.0);
    }
    set_viewport(right);
    plwind(0.0, double(n_cat), 0.0, y_hi);

    const double y_step = nice_step(y_hi, y_tick_target(viewport_chars().second));
    plcol0(kGrid);
    pen(1.0);
    plbox("", 0.0, 0, "g", y_step, 0);

    // Millimetres per world unit vertically and horizontally, to decide which labels fit.
    PLFLT sx0, sx1, sy0, sy1, vx0, vx1, vy0, vy1, def_ht, ht;
    plgspa(&sx0, &sx1, &sy0, &sy1);
    plgvpd(&vx0, &vx1, &vy0, &vy1);
    plgchr(&def_ht, &ht);
    const double mm_per_y = (vy1 - vy0) * (sy1 - sy0) / y_hi;
    const double mm_per_x = (vx1 - vx0) * (sx1 - sx0) / double(n_cat);
    const double bar_half = 0.31;

    for (size_t i = 0; i < n_cat; ++i) {
      const double x0 = double(i) + 0.5 - bar_half, x1 = double(i) + 0.5 + bar_half;
      double bottom = 0.0;
      for (size_t k = 0; k < n_stack; ++k) {
        const double v = stacks[k].values[i];
        if (v <= 0.0) continue;
        PLFLT rx[4] = {x0, x1, x1, x0}, ry[4] = {bottom, bottom, bottom + v, bottom + v};
        plcol0(PLINT(kFirstSeries + k));
        plfill(4, rx, ry);
        if (bottom > 0.0) {  // a white seam between parts
          plcol0(kWhite);
          pen(1.5);
          PLFLT ox[2] = {x0, x1}, oy[2] = {bottom, bottom};
          plline(2, ox, oy);
        }
        const std::string& text = part_text[k][i];
        const double text_mm = 0.62 * ht * double(text.size());
        if (!text.empty() && v * mm_per_y > 1.9 * ht && text_mm < 2 * bar_half * mm_per_x * 0.95) {
          const Colour c = plot_colour(k);
          const double luminance = (0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b) / 255.0;
          plcol0(luminance < 0.6 ? kWhite : kInk);
          plschr(0.0, 0.9);
          plptex(double(i) + 0.5, bottom + v / 2.0, 1.0, 0.0, 0.5, text.c_str());
          plschr(0.0, 1.0);
        }
        bottom += v;
      }
      if (!total_text[i].empty()) {
        plcol0(kInk);
        plptex(double(i) + 0.5, totals[i] + 1.1 * ht / mm_per_y, 1.0, 0.0, 0.5,
               total_text[i].c_str());
      }
      plcol0(kInk);
      plschr(0.0, 1.05);
      plmtex("b", 1.4, (double(i) + 0.5) / double(n_cat), 0.5, plain(categories[i]).c_str());
      plschr(0.0, 1.0);
    }

    draw_axes("", 0.0, y_step);
    draw_labels(title, "", o.y_label);

    // Legend entries top to bottom in the order the parts are stacked, bottom part last.
    std::vector<std::string> legend_names;
    std::vector<PLINT> boxes, lines;
    for (size_t k = n_stack; k-- > 0;) {
      legend_names.push_back(stacks[k].name);
      boxes.push_back(PLINT(kFirstSeries + k));
      lines.push_back(PLINT(kFirstSeries + k));
    }
    draw_legend(legend_names, lines, boxes, false, o.legend);
  });
}

}  // namespace roger
