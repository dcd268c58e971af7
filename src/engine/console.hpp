// Messages on standard output and standard error, each in one write(2): mpirun forwards several
// ranks' streams as the pieces arrive, so a message written in parts ("hemirad: error: ", then the
// text) can be split by, or glued to, another line.
#pragma once

#include <ostream>
#include <string>
#include <string_view>

namespace hemirad {

/// Writes `text` to `stream` whole: std::cout and std::cerr (what they buffered first) with one
/// write(2) on their descriptor, continued only where the system takes part of it (a pipe takes up
/// to 4096 bytes whole); any other stream gets `text` and a flush. Never throws.
void writeWhole(std::ostream& stream, std::string_view text) noexcept;

/// "hemirad: error: MESSAGE\n", with "(run 'hemirad help' for usage)\n" after a usage error, on
/// standard error as one write. Never throws.
void printError(const std::string& message, bool usage = false) noexcept;

}  // namespace hemirad
