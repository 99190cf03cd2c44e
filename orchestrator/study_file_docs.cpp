// demsa_study_file_docs DOCS: rewrites the key-by-key reference of docs/reference/study-file.md (between its
// `<!-- settings-table:begin -->` and `<!-- settings-table:end -->` markers) from the one settings table
// (experiments::settings_table(): the core rows and every experiment's), so that the docs follow the table. Run by
// every build (target study_file_docs); writes the file only when the table changed it.
// tests/orchestrator/study/test_settings.cpp checks the two agree.
#include "orchestrator/experiments/settings_docs.hpp"
#include "orchestrator/util/atomic_file.hpp"

#include <fmt/core.h>

#include <exception>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>

int main(int argc, char** argv) {
  if (argc != 2) {
    fmt::print(stderr, "usage: demsa_study_file_docs docs/reference/study-file.md\n");
    return 2;
  }
  try {
    std::ifstream in(argv[1]);
    if (!in) {
      fmt::print(stderr, "demsa_study_file_docs: {}: cannot read the file\n", argv[1]);
      return 3;
    }
    std::ostringstream text;
    text << in.rdbuf();
    const std::string file = text.str();
    const std::optional<std::string> regenerated = demsa::experiments::with_settings_table(file);
    if (!regenerated) {
      fmt::print(stderr, "demsa_study_file_docs: {}: no settings-table markers\n", argv[1]);
      return 2;
    }
    const std::string& updated = *regenerated;
    if (updated != file) {
      demsa::util::write_file_atomically(argv[1], updated);
      fmt::print("{}: the settings table regenerated\n", argv[1]);
    }
  } catch (const std::exception& x) {
    fmt::print(stderr, "demsa_study_file_docs: {}\n", x.what());
    return 3;
  }
  return 0;
}
