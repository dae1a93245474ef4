// cairo_file.h: cairo surfaces written through an AtomicFile, so a picture is never half-written.
#pragma once

#include <cairo.h>

#include "core/fileio.h"

namespace roger {

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
