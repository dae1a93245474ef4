#include "core/install.h"

namespace roger {

namespace fs = std::filesystem;

std::optional<fs::path> executable_path() {
  std::error_code ec;
  // A symbolic link to the program (e.g. /usr/local/bin/roger -> /opt/roger/bin/roger) resolves
  // to the program itself, so its data is found beside the real tree.
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec || exe.empty()) return std::nullopt;
  return exe;
}

std::optional<fs::path> installed_data_dir() {
  const std::optional<fs::path> exe = executable_path();
  if (!exe) return std::nullopt;
  std::error_code ec;
  const fs::path data = (exe->parent_path() / ROGER_DATA_FROM_BIN).lexically_normal();
  // scenarios/ is what every command needs first; a build tree has no such folder beside it.
  if (!fs::is_directory(data / "scenarios", ec)) return std::nullopt;
  return data;
}

}  // namespace roger
