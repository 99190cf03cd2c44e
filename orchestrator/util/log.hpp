#pragma once
// demsa's one logging style: lines on standard error ("demsa: warning: ...", "demsa: info: ..."), so that
// standard output carries only results (the JSON of `demsa status --json`, tables, CSV). Errors are not logged
// here: they are thrown (errors.hpp) and printed once by cli::run_cli().
#include <fmt/core.h>

#include <string>

namespace demsa::util::log {

/// Sends one line to standard error as "demsa: LEVEL: message".
void write(const char* level, const std::string& message);

template <typename... Args>
void info(fmt::format_string<Args...> format, Args&&... args) {
  write("info", fmt::format(format, std::forward<Args>(args)...));
}

template <typename... Args>
void warn(fmt::format_string<Args...> format, Args&&... args) {
  write("warning", fmt::format(format, std::forward<Args>(args)...));
}

}  // namespace demsa::util::log
