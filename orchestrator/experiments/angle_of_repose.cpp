#include "orchestrator/experiments/angle_of_repose.hpp"

namespace demsa::experiments {

namespace pp = demsa::postprocess;

pp::Particles without_base(const pp::Particles& particles, long base_particles) {
  if (base_particles <= 0) return particles;
  pp::Particles pile;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    if (particles.id[i] <= base_particles) continue;
    pile.id.push_back(particles.id[i]);
    pile.type.push_back(particles.type[i]);
    pile.x.push_back(particles.x[i]);
    pile.y.push_back(particles.y[i]);
    pile.z.push_back(particles.z[i]);
    pile.radius.push_back(particles.radius[i]);
  }
  return pile;
}

}  // namespace demsa::experiments
