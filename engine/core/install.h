// install.h: where an installed roger finds its Lua libraries, scenarios, curricula and scripts.
// `cmake --install build --prefix P` puts the program in P/bin and those folders in P/share/roger;
// the program finds them from its own location, so an installed tree works wherever it is copied.
#pragma once

#include <filesystem>
#include <optional>

namespace roger {

// The running program's own file (/proc/self/exe), or nullopt where the system does not say.
std::optional<std::filesystem::path> executable_path();

// The data folder of an installed program: <folder of the program>/../share/roger (as configured
// at build time) when it holds scenarios/; nullopt for a program run from its build tree.
std::optional<std::filesystem::path> installed_data_dir();

}  // namespace roger
