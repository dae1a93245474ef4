// plot.cpp: see plot.h. Writing a figure: every PLplot call happens under g_plplot_mutex, between
// one plinit and one plend, on a device and output file chosen per figure, into a temporary file
// that is checked and then renamed into place. The figures themselves are drawn by
// plot_curves.cpp and plot_bars.cpp in the frame of plot_frame.cpp.
#include "report/plot.h"

#include <fcntl.h>
#include <plplot.h>
#include <sys/statvfs.h>
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
#include "core/fileio.h"
#include "core/text.h"
#include "report/plot_internal.h"

namespace roger {

using namespace plot_internal;

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

// A temporary file beside the destination for PLplot to write; removed unless committed.
class TempFigure {
 public:
  TempFigure(const std::string& path, Format format) : path_(path), format_(format) {
    const fs::path target(path);
    if (target.filename().empty() || target.filename() == "." || target.filename() == "..")
      throw Error("cannot write figure '" + path + "': it names a folder, not a file");
    const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
    // PLplot treats "%n" in a file name as a family member number: keep it out of the name.
    if (dir.string().find("%n") != std::string::npos)
      throw Error("cannot write figure '" + path + "': PLplot cannot write into a folder "
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
        fail(std::strerror(err), err);
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
    if (!whole && nearly_full(temp_)) fail(std::strerror(ENOSPC), ENOSPC);
    if (!whole)
      fail("PLplot wrote an incomplete " + std::string(format_ == Format::kPng ? "PNG" : "SVG") +
           " (" + std::to_string(data.size()) + " bytes): is the disk full?");
    const int fd = ::open(temp_.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0 || ::fsync(fd) != 0) {
      const int err = errno;
      if (fd >= 0) ::close(fd);
      fail(std::strerror(err), err);
    }
    ::close(fd);
  }

  // Renames the verified temporary over the destination.
  void commit() {
    if (std::rename(temp_.c_str(), path_.c_str()) != 0) fail(std::strerror(errno), errno);
    committed_ = true;
    sync_folder_of(path_);  // the rename survives a crash of the machine, as fileio.h's do
  }

 private:
  // A failure of the system (err: its errno) is a FileError, which stops a batch run.
  [[noreturn]] void fail(const std::string& why, int err = 0) const {
    const std::string message = "cannot write figure '" + path_ + "': " + why;
    if (err != 0) throw FileError(message, path_, err);
    throw Error(message);
  }

  // Whether the file's filesystem has under 1 MiB left: PLplot reports no failed write, so a
  // figure cut short on such a disk is taken as a full disk.
  static bool nearly_full(const std::string& file) {
    struct statvfs fs_info;
    const fs::path dir = fs::path(file).parent_path();
    if (::statvfs(dir.empty() ? "." : dir.c_str(), &fs_info) != 0) return false;
    return uint64_t(fs_info.f_bavail) * fs_info.f_frsize < (uint64_t(1) << 20);
  }

  std::string path_, temp_;
  Format format_;
  bool committed_ = false;
};

// Palette: colour-blind-safe (Okabe & Ito), cycled.
const Colour kPalette[] = {{0, 114, 178},   {213, 94, 0},   {0, 158, 115}, {204, 121, 167},
                           {230, 159, 0},   {86, 180, 233}, {90, 90, 90}};
constexpr size_t kPaletteSize = sizeof(kPalette) / sizeof(kPalette[0]);

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

}  // namespace

namespace plot_internal {

// The format named by path's extension, or an Error naming the two accepted ones.
Format format_of(const std::string& path) {
  const std::string ext = fs::path(path).extension().string();
  const std::string lower = lower_ascii(ext);
  if (lower == ".png") return Format::kPng;
  if (lower == ".svg") return Format::kSvg;
  const std::string why =
      ext.empty() ? std::string("it has no extension") : "unknown extension '" + ext + "'";
  throw Error("cannot write figure '" + path + "': " + why + "; use .png or .svg");
}

// Line style of the index-th series: solid, then dashed patterns once the palette repeats.
PLINT line_style(size_t index) { return PLINT(1 + (index / kPaletteSize) % 8); }

// PLplot text with its escape character doubled, so '#' in a name is printed as itself.
std::string plain(const std::string& text) {
  std::string out;
  for (char c : text) {
    out += c;
    if (c == '#') out += '#';
  }
  return out;
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
      throw Error("cannot write figure '" + temp->path() + "': PLplot: " + e.what());
    }
    temp->verify();
  }
  for (auto& temp : temps) temp->commit();
}

// A value as an error message shows it.
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

}  // namespace plot_internal

Colour plot_colour(size_t index) { return kPalette[index % kPaletteSize]; }

}  // namespace roger
