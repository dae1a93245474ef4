// batch_internal.h: what the batch module's files share and nobody else needs.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "batch/batch.h"

namespace roger::batch_detail {

// The whole content of a file ("" when it cannot be read).
std::string read_text(const std::string& path);

// The first line of a message.
std::string first_line(const std::string& s);

// A trial's state on disk: "ok" (filling `result`), "failed" (filling `error`, also for an
// unreadable result) or "pending".
std::string trial_status(const std::string& out, const PlannedTrial& t, nlohmann::json& result, std::string& error);

}  // namespace roger::batch_detail
