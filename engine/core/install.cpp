#include "core/install.h"

#include <dlfcn.h>
#include <link.h>

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <string>

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

namespace {

// Where the program's own image starts in memory (dladdr's dli_fbase of code inside it): the lowest
// loaded segment of the first object dl_iterate_phdr lists, which is the program.
int note_program_start(dl_phdr_info* info, size_t, void* start) {
  uintptr_t lowest = UINTPTR_MAX;
  for (int k = 0; k < info->dlpi_phnum; ++k)
    if (info->dlpi_phdr[k].p_type == PT_LOAD)
      lowest = std::min(lowest, uintptr_t(info->dlpi_addr + info->dlpi_phdr[k].p_vaddr));
  *static_cast<uintptr_t*>(start) = lowest;
  return 1;  // the first entry is the program; stop there
}

// The file of the shared object this code is in (the Python module's), or nullopt when it is the
// program itself or the system does not say.
std::optional<fs::path> shared_object_path(const std::optional<fs::path>& exe) {
  Dl_info info{};
  if (!dladdr(reinterpret_cast<void*>(&installed_data_dir), &info) || !info.dli_fname || !*info.dli_fname)
    return std::nullopt;
  // For code in the program itself glibc names argv[0] ("roger" when found on PATH), which is no
  // path to it (found by a probe: roger run from PATH took it for the Python module, found no data
  // beside "roger" and read the source tree it was built from, or a data_dir.txt in the current
  // folder): the program is told by where its image starts, which its file name cannot tell.
  uintptr_t program_start = 0;
  dl_iterate_phdr(note_program_start, &program_start);
  if (uintptr_t(info.dli_fbase) == program_start) return std::nullopt;
  std::error_code ec;
  const fs::path object = fs::weakly_canonical(info.dli_fname, ec);
  if (ec || !object.is_absolute() || (exe && fs::equivalent(object, *exe, ec))) return std::nullopt;
  return object;
}

std::optional<fs::path> find_installed_data_dir() {
  const std::optional<fs::path> exe = executable_path();
  std::error_code ec;
  // scenarios/ is what every command needs first; a build tree has no such folder beside it.
  const auto holds_data = [&](const fs::path& data) { return fs::is_directory(data / "scenarios", ec); };
  // Inside the installed Python module (P/lib/python3.X/dist-packages/roger/_roger...so), whose
  // interpreter is not roger: the prefix's data above the module's own file, found by climbing,
  // or the one recorded beside it, so that an installed package reads its own data, not the source
  // tree it was built from (which only a package with neither falls back to).
  if (const std::optional<fs::path> object = shared_object_path(exe)) {
    for (fs::path up = object->parent_path(); !up.empty() && up != up.root_path(); up = up.parent_path())
      if (holds_data(up / ROGER_DATA_FROM_PREFIX)) return (up / ROGER_DATA_FROM_PREFIX).lexically_normal();
    // A package installed outside its prefix (-DROGER_PYTHON_INSTALL_DIR): the data folder cmake
    // --install recorded beside it (engine/python/CMakeLists.txt).
    std::ifstream recorded(object->parent_path() / "data_dir.txt");
    std::string line;
    if (recorded && std::getline(recorded, line) && !line.empty() && holds_data(line)) return fs::path(line);
    return std::nullopt;
  }
  if (!exe) return std::nullopt;
  const fs::path data = (exe->parent_path() / ROGER_DATA_FROM_BIN).lexically_normal();
  if (!holds_data(data)) return std::nullopt;
  return data;
}

}  // namespace

std::optional<fs::path> installed_data_dir() {
  static const std::optional<fs::path> found = find_installed_data_dir();  // where the binary is does not change
  return found;
}

}  // namespace roger
