// batch_internal.h: what the batch module's files share and nobody else needs.
#pragma once

#include <string>

namespace roger::batch_detail {

// The whole content of a file ("" when it cannot be read).
std::string read_text(const std::string& path);

// The first line of a message.
std::string first_line(const std::string& s);

}  // namespace roger::batch_detail
