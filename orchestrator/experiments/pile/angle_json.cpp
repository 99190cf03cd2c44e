#include "orchestrator/experiments/pile/angle_json.hpp"

namespace demsa::experiments::pile {

namespace pp = demsa::postprocess;

nlohmann::json angle_result_json(const pp::PileAngleResult& r, const std::string& dump, const std::string& case_json) {
  nlohmann::json j;
  j["dump"] = dump;
  j["case_json"] = case_json.empty() ? nlohmann::json(nullptr) : nlohmann::json(case_json);
  j["options"] = {{"pedestal_radius_m", r.options.pedestal_radius},
                  {"pedestal_top_m", r.options.pedestal_top},
                  {"axis_x_m", r.options.axis_x},
                  {"axis_y_m", r.options.axis_y},
                  {"particle_type", r.options.particle_type},
                  {"directions", r.options.directions},
                  {"levels", r.options.levels},
                  {"level_low", r.options.low_level()},
                  {"level_high", r.options.high_level()},
                  {"min_points", r.options.min_points},
                  {"point", pp::to_string(r.options.point)},
                  {"estimator", pp::to_string(r.options.estimator)},
                  {"target_angle_deg", r.options.target_angle}};
  j["particles_total"] = r.particles_total;
  j["particles_on_pedestal"] = r.particles_on_pedestal;
  j["pile_height_m"] = r.pile_height;
  j["level_heights_m"] = r.level_heights;
  j["directions_used"] = r.directions_used;
  j["angle_deg"] = r.angle;
  j["angle_sd_deg"] = r.angle_sd;
  j["angle_min_deg"] = r.angle_min;
  j["angle_max_deg"] = r.angle_max;
  j["angle_error_deg2"] = r.angle_error;
  nlohmann::json lines = nlohmann::json::array();
  for (const pp::DirectionLine& l : r.lines)
    lines.push_back({{"direction", l.direction},
                     {"phi_deg", l.phi},
                     {"ex", l.ex},
                     {"ey", l.ey},
                     {"points", l.points},
                     {"used", l.used},
                     {"angle_deg", l.angle},
                     {"rms_distance_m", l.rms_distance},
                     {"radial_low_m", l.radial_low},
                     {"height_low_m", l.height_low},
                     {"radial_high_m", l.radial_high},
                     {"height_high_m", l.height_high}});
  j["lines"] = std::move(lines);
  nlohmann::json boundary = nlohmann::json::array();
  for (const pp::BoundaryParticle& b : r.boundary)
    boundary.push_back({{"direction", b.direction},
                        {"level", b.level},
                        {"id", b.id},
                        {"x_m", b.x},
                        {"y_m", b.y},
                        {"z_m", b.z},
                        {"radius_m", b.radius},
                        {"radial_m", b.radial},
                        {"height_m", b.height}});
  j["boundary"] = std::move(boundary);
  return j;
}

}  // namespace demsa::experiments::pile
