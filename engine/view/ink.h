// ink.h: the colours, cairo helpers and scales shared by pictures (render.cpp) and animations
// (animation.cpp), so a frame and the timeline drawn under it read as one picture.
#pragma once

#include <cairo.h>

#include <cmath>

#include "core/spec.h"

namespace roger::ink {

// An RGB colour in cairo's 0..1 range.
struct Rgb {
  double r, g, b;
};

// From 0..255 components.
inline Rgb rgb(int r, int g, int b) { return {r / 255.0, g / 255.0, b / 255.0}; }
// From a scene colour.
inline Rgb rgb(const Colour& c) { return {c.r / 255.0, c.g / 255.0, c.b / 255.0}; }
// The same hue, darker by the factor f in [0, 1].
inline Rgb darker(Rgb c, double f) { return {c.r * f, c.g * f, c.b * f}; }
// Makes c the source colour of cr.
inline void set(cairo_t* cr, Rgb c, double alpha = 1.0) {
  cairo_set_source_rgba(cr, c.r, c.g, c.b, alpha);
}

inline const Rgb kInk = rgb(40, 44, 52);         // text and outlines
inline const Rgb kFaintInk = rgb(120, 124, 132); // secondary text, ticks
inline const Rgb kWhite = rgb(255, 255, 255);

// A round tick spacing giving at most about ten intervals over span: the arena's metre scale
// (world_picture.cpp) and the timeline's seconds (timeline.cpp).
inline double nice_step(double span) {
  const double raw = span / 10.0;
  const double p = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 2.5, 5.0, 10.0})
    if (m * p >= raw - 1e-12) return m * p;
  return 10 * p;
}

}  // namespace roger::ink
