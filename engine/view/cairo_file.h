// cairo_file.h: cairo surfaces written through an AtomicFile, so a picture is never half-written,
// and what owns a drawing's surface (pictures, render.cpp, and animations, animation.cpp).
#pragma once

#include <cairo.h>

#include "core/fileio.h"

namespace roger {

constexpr int kMaxPicturePixels = 32767;  // cairo's image surface limit per side

// Owns a cairo surface and context for the length of one drawing.
struct Canvas {
  cairo_surface_t* surface = nullptr;
  cairo_t* cr = nullptr;
  ~Canvas() {
    if (cr) cairo_destroy(cr);
    if (surface) cairo_surface_destroy(surface);
  }
};

// A cairo write callback appending to the AtomicFile given as the closure.
inline cairo_status_t cairo_write_to_file(void* closure, const unsigned char* data, unsigned int length) {
  auto* file = static_cast<AtomicFile*>(closure);
  file->append(data, length);
  return file->ok() ? CAIRO_STATUS_SUCCESS : CAIRO_STATUS_WRITE_ERROR;
}

// Throws for a failed write or a cairo failure, preferring the operating system's reason.
inline void check_cairo(AtomicFile& file, cairo_status_t status) {
  file.check();
  if (status != CAIRO_STATUS_SUCCESS) file.fail(cairo_status_to_string(status));
}

}  // namespace roger
