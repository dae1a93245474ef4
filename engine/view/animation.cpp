// animation.cpp: an episode written as a folder (frames, episode.json, index.html) or as one summary
// PNG; the timeline is drawn by timeline.cpp and the page filled by episode_page.cpp.
#include "view/animation.h"
#include "view/animation_internal.h"

#include "core/fileio.h"
#include "view/cairo_file.h"
#include "view/ink.h"

#include <cairo.h>
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <random>
#include <sstream>

#include <nlohmann/json.hpp>

#include "control/control.h"
#include "core/error.h"
#include "core/interrupt.h"
#include "core/text.h"

namespace roger {
namespace anim {

// A number without trailing zeros or a negative zero.
std::string number_text(double v) {
  if (std::fabs(v) < 1e-9) v = 0;
  return format("%g", v);
}

// Names come from Lua scripts and may hold any bytes; cairo refuses invalid UTF-8 (and then draws
// nothing more), and the JSON writer would throw, so invalid bytes become '?'.
std::string valid_utf8(const std::string& s) {
  std::string out;
  out.reserve(s.size());
  size_t i = 0;
  while (i < s.size()) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    int len = c < 0x80 ? 1 : (c >> 5) == 0x6 ? 2 : (c >> 4) == 0xE ? 3 : (c >> 3) == 0x1E ? 4 : 0;
    bool ok = len > 0 && i + len <= s.size() && !(len == 2 && c < 0xC2);
    for (int k = 1; ok && k < len; ++k)
      ok = (static_cast<unsigned char>(s[i + k]) & 0xC0) == 0x80;
    if (ok && len == 1 && c < 0x20) ok = false;  // control characters would break a label
    if (ok) {
      out.append(s, i, size_t(len));
      i += size_t(len);
    } else {
      out += '?';
      ++i;
    }
  }
  return out;
}

// frame_0000.png, ...; more digits only beyond 9999 frames.
std::string frame_name(size_t i) { return format("frame_%04zu.png", i); }

}  // namespace anim

// The episode's internals (animation_internal.h), used beside the public functions below.
using namespace anim;

namespace {

namespace fs = std::filesystem;

// ---- files
// ----------------------------------------------------------------------------------------------

// Writes content to path atomically.
void write_text_file(const std::string& path, const std::string& content) {
  AtomicFile file(path, "animation: cannot write");
  file.append(content);
  file.commit();
}

// Lets paint draw on a width x height image and writes it atomically to path as PNG.
template <class Paint>
void write_png(const std::string& path, long width, long height, Paint paint) {
  if (width < 1 || height < 1 || width > kMaxPicturePixels || height > kMaxPicturePixels) {
    std::ostringstream os;
    os << "animation: cannot write '" << path << "': a " << width << " x " << height
       << " picture is outside 1 to " << kMaxPicturePixels
       << " pixels per side (use a smaller --width)";
    throw Error(os.str());
  }
  AtomicFile file(path, "animation: cannot write");
  Canvas canvas;
  canvas.surface = cairo_image_surface_create(CAIRO_FORMAT_ARGB32, int(width), int(height));
  check_cairo(file, cairo_surface_status(canvas.surface));
  canvas.cr = cairo_create(canvas.surface);
  set(canvas.cr, kWhite);
  cairo_paint(canvas.cr);
  paint(canvas.cr);
  check_cairo(file, cairo_status(canvas.cr));
  cairo_surface_flush(canvas.surface);
  check_cairo(file, cairo_surface_write_to_png_stream(canvas.surface, &cairo_write_to_file, &file));
  file.commit();
}

// The frame index a file name stands for, or -1 when it is not one of ours.
long frame_index(const std::string& name) {
  const std::string prefix = "frame_", suffix = ".png";
  if (name.size() <= prefix.size() + suffix.size() || name.compare(0, prefix.size(), prefix) != 0 ||
      name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0)
    return -1;
  const std::string digits =
      name.substr(prefix.size(), name.size() - prefix.size() - suffix.size());
  if (digits.size() > 9 ||
      !std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; }))
    return digits.size() > 9 ? LONG_MAX : -1;
  return std::stol(digits);
}

// Makes the folder (and its parents) or says why it cannot be used.
void make_folder(const std::string& folder) {
  if (folder.empty()) throw Error("animation: the output folder name is empty");
  std::error_code ec;
  if (fs::exists(folder, ec) && !fs::is_directory(folder, ec))
    throw Error("animation: cannot write into '" + folder + "': it exists and is not a folder");
  fs::create_directories(folder, ec);
  if (ec) throw Error("animation: cannot create folder '" + folder + "': " + ec.message());
}

// Everything that can be wrong with the inputs, found before any file is touched.
RenderOptions check_inputs(const WorldSpec& spec, const EpisodeResult& ep,
                           const AnimationOptions& o, const std::string& where) {
  if (ep.frames.empty())
    throw Error("animation: the episode has no frames to render into '" + where +
                "'; record them with EpisodeOptions::record_every > 0");
  if (!std::isfinite(o.fps) || o.fps <= 0 || o.fps > 1000)
    throw Error("animation: fps must be above 0 and at most 1000, got " + number_text(o.fps));
  for (size_t i = 0; i < ep.frames.size(); ++i) {
    const size_t n = ep.frames[i].objects.size();
    if (n != 0 && n != spec.objects.size())
      throw Error("animation: frame " + std::to_string(i) + " has " + std::to_string(n) +
                  " object poses but the world spec has " + std::to_string(spec.objects.size()) +
                  " objects: was the episode run in this world?");
  }
  RenderOptions fo = o.frame;
  if (fo.title.empty()) fo.title = o.title;
  fo.title = valid_utf8(fo.title);
  picture_size(spec, fo);  // throws for a bad width or an empty arena
  return fo;
}

// Removes frame files a longer, earlier rendering left beyond the new count.
void remove_stale_frames(const std::string& folder, size_t count) {
  std::error_code ec;
  std::vector<fs::path> stale;
  for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    const long k = frame_index(name);
    if (k < 0) continue;
    if (size_t(k) >= count || name != frame_name(size_t(k))) stale.push_back(it->path());
  }
  if (ec) throw Error("animation: cannot list folder '" + folder + "': " + ec.message());
  for (const fs::path& p : stale) {
    fs::remove(p, ec);
    if (ec)
      throw Error("animation: cannot remove the old frame '" + p.string() +
                  "' (the folder would mix two episodes): " + ec.message());
  }
}

}  // namespace

bool render_episode_writes(const std::string& file_name) {
  return file_name == "episode.json" || file_name == "index.html" || frame_index(file_name) >= 0;
}

namespace {

// Removes what a rendering killed part-way left in the folder: its staging folder (StagedFiles'
// hidden .staged<pid>-...tmp) and a file caught half-written (.frame_0017.png.tmp<pid>-...).
void remove_leftovers(const std::string& folder) {
  std::error_code ec;
  std::vector<fs::path> left;
  for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (!is_writer_leftover(name)) continue;
    if (name.rfind(".staged", 0) == 0 || render_episode_writes(name.substr(1, name.rfind(".tmp") - 1)))
      left.push_back(it->path());
  }
  for (const fs::path& p : left) fs::remove_all(p, ec);
}

}  // namespace

// The files are written into a staging folder and moved in together, the page last, once every
// one is whole: a rendering stopped part-way (Ctrl-C, a full disk) leaves the folder as it was
// (found by a probe: Ctrl-C left the first frames of a new episode among an old one's files).
void render_episode(const WorldSpec& spec, const EpisodeResult& episode, const std::string& folder,
                    const AnimationOptions& options) {
  const RenderOptions fo = check_inputs(spec, episode, options, folder);
  make_folder(folder);
  remove_leftovers(folder);
  StagedFiles staged(folder);
  std::vector<std::string> names;
  const Timeline tl = make_timeline(episode);
  const PictureSize world = picture_size(spec, fo);
  const double u = world.width / 1000.0;
  const double tl_h = options.show_timeline ? timeline_height(tl, TimelineMode::kFrame, u) : 0.0;
  const long width = world.width, height = world.height + long(std::ceil(tl_h));

  for (size_t i = 0; i < episode.frames.size(); ++i) {
    throw_if_interrupted();
    const Frame& f = episode.frames[i];
    names.push_back(frame_name(i));
    write_png(staged.stage(names.back()), width, height, [&](cairo_t* cr) {
      draw_frame(cr, spec, f, fo, world.width, world.height);
      if (options.show_timeline) {
        const Cursor c{std::isfinite(f.time) ? f.time : 0.0, 0, tl.frame_ticks[i]};
        draw_timeline(cr, tl, TimelineMode::kFrame, {c}, options.dim_future, 0,
                            world.height, world.width, u);
      }
    });
  }
  const json data = episode_json(spec, episode, tl, options);
  write_text_file(staged.stage("episode.json"), data.dump(1, ' ', false, json::error_handler_t::replace) + "\n");
  write_text_file(staged.stage("index.html"), page_html(spec, episode, tl, options, data));
  names.push_back("episode.json");
  names.push_back("index.html");  // the page last: once it is replaced, every file beside it is the new one
  throw_if_interrupted();
  staged.commit(names);
  remove_stale_frames(folder, episode.frames.size());
}

void render_episode_summary(const WorldSpec& spec, const EpisodeResult& episode,
                            const std::string& path, const AnimationOptions& options, int panels) {
  const std::string ext = lower_ascii(fs::path(path).extension().string());
  if (ext != ".png")
    throw Error("animation: cannot write summary '" + path + "': the summary is a PNG, name it .png");
  if (panels < 1)
    throw Error("animation: a summary needs at least one panel, got " + std::to_string(panels));
  const RenderOptions fo = check_inputs(spec, episode, options, path);
  const Timeline tl = make_timeline(episode);

  // Evenly spaced in frame order, first and last included (frames are evenly spaced in time but
  // for the final one, taken when the goal held).
  const size_t count = episode.frames.size();
  const size_t n = std::min(size_t(panels), count);
  std::vector<size_t> pick;
  for (size_t i = 0; i < n; ++i)
    pick.push_back(n == 1 ? count - 1
                          : size_t(std::lround(double(i) * double(count - 1) / double(n - 1))));

  const PictureSize panel = picture_size(spec, fo);
  const double u = panel.width / 1000.0;
  const long width = long(panel.width) * long(n);
  const long height = panel.height + long(std::ceil(timeline_height(tl, TimelineMode::kSummary, u)));
  write_png(path, width, height, [&](cairo_t* cr) {
    std::vector<Cursor> cursors;
    for (size_t p = 0; p < n; ++p) {
      const Frame& f = episode.frames[pick[p]];
      cairo_save(cr);
      cairo_translate(cr, double(p) * panel.width, 0);
      draw_frame(cr, spec, f, fo, panel.width, panel.height);
      // The badge sits in the header's empty left corner, left of the title.
      number_badge(cr, u, 30 * u, 21 * u, int(p + 1));
      if (p > 0) {
        set(cr, kRule);
        cairo_set_line_width(cr, 1.0 * u);
        cairo_move_to(cr, 0.5 * u, 8 * u);
        cairo_line_to(cr, 0.5 * u, panel.height - 8 * u);
        cairo_stroke(cr);
      }
      cairo_restore(cr);
      cursors.push_back({std::isfinite(f.time) ? f.time : 0.0, int(p + 1), tl.frame_ticks[pick[p]]});
    }
    draw_timeline(cr, tl, TimelineMode::kSummary, cursors, false, 0, panel.height, double(width),
                  u);
  });
}

}  // namespace roger
