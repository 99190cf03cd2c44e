// libFuzzer target for the LIGGGHTS dump reader: any input must either parse or raise ParseError, never crash,
// hang or allocate what the input merely claims. Built and run by bench/fuzz-dump-reader.sh (needs clang++), not
// by CMake and not in CI.
#include "postprocess/dump.hpp"

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace demsa::postprocess;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  DumpReaderOptions options;
  options.max_line_bytes = 4096;
  try {
    DumpReader reader(std::string(text), "fuzz.dump", options);
    DumpFrame frame;
    while (reader.next(frame)) {
      try {
        const Particles particles = particles_from_frame(frame);
        (void)particles;
      } catch (const ParseError&) {
      }
    }
  } catch (const ParseError&) {
  }
  return 0;
}
