// libFuzzer target for the study-file parser (experiments::parse_study: toml++ and the settings table): any input must
// either give a study or raise util::UserError naming the file, never crash, hang, narrow an integer or allocate
// what the input merely claims. Built and run by bench/fuzz-study-file.sh (needs clang++), not by CMake and not in CI.
#include "orchestrator/experiments/registry.hpp"
#include "orchestrator/study/config.hpp"
#include "orchestrator/study/settings.hpp"
#include "orchestrator/util/errors.hpp"

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace demsa;
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const study::StudyConfig config = experiments::parse_study(text, "fuzz.toml");
    // An accepted study is hashed and shown as the docs and messages show it.
    (void)study::design_hash(config);
    for (const study::Setting& s : experiments::settings_table().rows()) (void)s.show(config);
  } catch (const util::UserError& e) {
    // Every refusal names the file.
    if (std::string(e.what()).rfind("fuzz.toml", 0) != 0) std::abort();
  }
  return 0;
}
