#pragma once
// The paper's particle sets (Table 2), the one home of the radii that the `preset = "set1" | "set2"` key of an
// experiment's section names (pile, incline, draw-down: their settings.cpp). Set 1 is also study::RadiusDistribution's
// default.
#include "orchestrator/study/config.hpp"

#include <string_view>

namespace demsa::experiments {

/// Set 1: radii in [1, 3.5] mm, mean 2 mm, sd 0.5 mm (the pile pours 6000 of them).
inline const study::RadiusDistribution k_set1_radii{1.0e-3, 3.5e-3, 2.0e-3, 0.5e-3};
/// Set 2: radii in [0.8, 2.5] mm, mean 1.5 mm, sd 0.35 mm (the pile pours 8000 of them).
inline const study::RadiusDistribution k_set2_radii{0.8e-3, 2.5e-3, 1.5e-3, 0.35e-3};

/// The radii of a preset: `set1`, else `set2` (the settings rows admit no other name).
inline const study::RadiusDistribution& preset_radii(std::string_view preset) {
  return preset == "set1" ? k_set1_radii : k_set2_radii;
}

}  // namespace demsa::experiments
