// libFuzzer target for the oedometer plate-file readers (plate_history.txt, plate_states.txt) and the line reader
// under them: any input must either parse or raise ParseError, never crash, hang or hold more than the reader's
// limits. Whatever parses must also satisfy the rules the reader promises (finite values, loads that never
// decrease, plate positions within 1 km), and the states derived from a history must measure. Built and run by
// bench/fuzz-plate-reader.sh (needs clang++), not by CMake and not in CI.
#include "postprocess/oedometer.hpp"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

namespace {

void require(bool ok) {
  if (!ok) std::abort();  // a broken promise of the reader: libFuzzer saves the input
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace demsa::postprocess;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const PlateHistory h = parse_plate_history(text, "plate_history.txt");
    require(h.load_N.size() == h.size() && h.plate_z_m.size() == h.size() && h.force_N.size() == h.size());
    for (std::size_t i = 0; i < h.size(); ++i) {
      require(std::isfinite(h.load_N[i]) && h.load_N[i] >= 0.0 && std::isfinite(h.force_N[i]));
      require(std::fabs(h.plate_z_m[i]) <= 1.0e3);
      if (i > 0) require(h.load_N[i] >= h.load_N[i - 1]);
    }
    const std::vector<PlateState> states = states_from_history(h, 1.0);
    if (!states.empty()) {
      const OedometerResult r = measure_oedometer(states);
      require(r.steps.size() == states.size());
    }
  } catch (const ParseError&) {
  } catch (const InputError&) {
  }
  try {
    const std::vector<PlateState> states = parse_plate_states(text, "plate_states.txt");
    for (std::size_t i = 0; i < states.size(); ++i) {
      require(std::isfinite(states[i].load_N) && std::isfinite(states[i].plate_z_m));
      if (i > 0) require(states[i].load_N >= states[i - 1].load_N);
    }
    if (!states.empty()) {
      const OedometerResult r = measure_oedometer(states);
      for (const OedometerStep& s : r.steps) require(std::isfinite(s.settlement_m) && std::isfinite(s.stress_Pa));
    }
  } catch (const ParseError&) {
  } catch (const InputError&) {
  }
  return 0;
}
