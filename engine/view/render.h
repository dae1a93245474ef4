// Module view: what a person looks at. Owns world pictures, episode animations and the replay
// page. Depends on learn and below; must not depend on script, batch, report or cli.
//
// render.h: pictures of one moment of a world (PNG or SVG) for researchers debugging controllers.
// A picture shows the arena with a metric scale, goals, obstacles, objects, Roger (base, arms,
// hands, eyes and their fields of view), the stereo fix, contact forces, and both eyes' 1-D images
// as colour strips below the arena. Files are written atomically: a reader never sees half a
// picture.
#pragma once

#include <cairo.h>

#include <cstdint>
#include <string>
#include <vector>

#include "core/robot.h"
#include "core/spec.h"
#include "sim/world.h"

namespace roger {

// What to draw and how large. Lengths in metres are world lengths; the rest scales with width_px.
struct RenderOptions {
  int width_px = 1000;              // picture width; the height follows from the arena's shape
  bool show_fields_of_view = true;  // the eyes' fields of view as wedges, and their sight lines
  bool show_images = true;          // the two 1-D images as colour strips below the arena
  bool show_contacts = true;        // touch forces as arrows at the contact points
  bool show_grid = false;           // light lines at every metric tick across the floor
  bool show_labels = true;          // names of goals, objects and obstacles
  bool show_status = true;          // a text line with the stereo fix and the touch forces
  std::string title;                // drawn top left; the scenario and seed are added beside it
  double arrow_metres_per_newton = 0.02;  // contact arrow length per newton of normal force
  double arrow_max_metres = 0.45;         // cap, so a collision spike does not cross the arena
};

// A picture's size in pixels (an SVG's size is in px as well).
struct PictureSize {
  int width = 0, height = 0;
};

// The size render_frame uses for one frame of spec: width_px wide, as tall as the layout needs.
PictureSize picture_size(const WorldSpec& spec, const RenderOptions& options = {});

// Draws one frame into the rectangle (0, 0)-(width, height) of cr, for callers that own the surface
// (animations, mosaics). Leaves cr's state as it found it; throws roger::Error (before drawing) for
// an empty arena or frame poses that do not match spec.
void draw_frame(cairo_t* cr, const WorldSpec& spec, const Frame& frame,
                const RenderOptions& options, double width, double height);

// Where a world point lands in a width x height picture drawn by draw_frame (device pixels, y
// down), so callers can overlay their own drawing (paths, occupancy) in register with the frame.
Vec2 picture_point(const WorldSpec& spec, const RenderOptions& options, double width, double height,
                   const Vec2& world);

// Draws one moment of a world to path (.png or .svg by extension, case-insensitive). Throws
// roger::Error for another extension, an unwritable path, or frame poses that do not match spec.
void render_frame(const WorldSpec& spec, const Frame& frame, const std::string& path,
                  const RenderOptions& options = {});

// A picture in memory: height rows of width pixels, each 3 bytes (red, green, blue), row after row
// from the top: what the Python module hands a Gymnasium user as an H x W x 3 uint8 array.
struct RgbPicture {
  int width = 0, height = 0;
  std::vector<uint8_t> pixels;  // width * height * 3
};

// Draws one moment of a world as render_frame does, into memory. Throws roger::Error like
// render_frame for sizes, arenas and frames it cannot draw.
RgbPicture render_rgb(const WorldSpec& spec, const Frame& frame, const RenderOptions& options = {});

// Draws several frames of one world as a mosaic of panels, each picture_size(spec, options), with
// `columns` panels per row (0: all in one row). Same file rules as render_frame; no frames is an
// error.
void render_frames(const WorldSpec& spec, const std::vector<Frame>& frames, const std::string& path,
                   const RenderOptions& options = {}, int columns = 0);

}  // namespace roger
