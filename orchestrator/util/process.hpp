#pragma once
// Starting other programs: the one place where demsa forks (after ccache's util/exec.hpp and ninja's
// subprocess.h). Programs are started from an argv, never through a shell.
#include <filesystem>

namespace demsa::util {

/// Absolute path of the running demsa (/proc/self/exe); "demsa" when it cannot be read.
std::filesystem::path self_executable();

}  // namespace demsa::util
