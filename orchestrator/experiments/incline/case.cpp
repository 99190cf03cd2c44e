#include "orchestrator/experiments/incline/incline.hpp"

#include "orchestrator/experiments/case_record.hpp"
#include "orchestrator/experiments/registry.hpp"
#include "orchestrator/study/folder.hpp"
#include "orchestrator/util/errors.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>

// The incline's case: its probes (radii drawn from the study seed, one lane each) and the files of its folder.
namespace demsa::experiments::incline {

using namespace demsa::study;

namespace fs = std::filesystem;

namespace {

class InclineDraft final : public CaseDraft {
 public:
  InclineDraft(const StudyConfig& config, std::uint64_t seed)
      : m_config(config),
        m_radii(truncated_normal_radii(settings(config).radii,
                                       settings(config).rolling_probes + settings(config).sliding_probes, seed)) {}
  double smallest_radius() const override { return *std::min_element(m_radii.begin(), m_radii.end()); }
  CaseWritten write(const Material& m, const TimestepChoice& ts, Params& params, const fs::path& dir) const override;

 private:
  const StudyConfig& m_config;
  std::vector<double> m_radii;  ///< rolling probes first, then the sliding ones
};

CaseWritten InclineDraft::write(const Material& m, const TimestepChoice& ts, Params& params,
                                const fs::path& dir) const {
  const InclineSettings& s = settings(m_config);
  const long probes = static_cast<long>(m_radii.size());
  const long settle_steps = steps_for(s.settle_time, ts.dt, "[incline] settle_time");
  const long record_steps = steps_for(s.record_angle / s.tilt_rate, ts.dt, "[incline] record_angle / tilt_rate");
  const long records =
      static_cast<long>(std::ceil(s.max_angle / (s.tilt_rate * static_cast<double>(record_steps) * ts.dt) - 1e-9));
  check_run_count(records, record_steps, "[incline] record_angle / tilt_rate");
  params.comment("incline: a tilting plate of the wall material");
  params.integer("rolling_probes", s.rolling_probes, "atoms 1..rolling_probes roll freely");
  params.integer("sliding_probes", s.sliding_probes, "the others have their rotation locked");
  params.integer("settle_steps", settle_steps, "on the level plate before the tilt");
  params.number("tilt_rate", s.tilt_rate, "gravity turns at this rate [deg/s]");
  params.integer("record_steps", record_steps, "probes recorded every this many steps");
  params.integer("records", records, "records up to max_angle");
  params.number("stop_x", s.stop_distance, "a probe further down the slope is removed [m]");

  // One lane per probe, across the slope (y), all at x = 0 resting on the plate.
  const double width = s.lane_spacing * static_cast<double>(probes);
  // Down the slope the box reaches twice stop_distance and 0.1 m more: a probe is removed at the end of a record
  // interval, and one that has run stop_distance on the plate (at most sqrt(2 |g| stop_distance), 2.4 m/s for 0.3 m)
  // covers less than that in an interval (0.05 s by default), so it is removed rather than lost.
  std::string data = data_header("demsa incline: the probes", probes, -0.02, 2 * s.stop_distance + 0.1,
                                 -width / 2 - 0.01, width / 2 + 0.01, -0.002, 0.05);
  for (long i = 0; i < probes; ++i) {
    const double r = m_radii[static_cast<std::size_t>(i)];
    const double y = (static_cast<double>(i) - static_cast<double>(probes - 1) / 2.0) * s.lane_spacing;
    data += atom_line(i + 1, Particle{0.0, y, r, r}, m.density);
  }
  write_text(dir / "incline_probes.data", data);
  write_text(dir / k_case_input, with_rolling_model(template_text("incline.liggghts"), m_config.contact));

  CaseWritten w;
  w.particles = probes;
  w.assembly = {{"particles", probes},
                {"radius_min_m", *std::min_element(m_radii.begin(), m_radii.end())},
                {"radius_max_m", *std::max_element(m_radii.begin(), m_radii.end())}};
  // Everything the measurement needs (incline.cpp), so that `demsa measure CASE` measures it the same way.
  w.experiment = {{"rolling_probes", s.rolling_probes}, {"sliding_probes", s.sliding_probes},
                  {"lane_spacing_m", s.lane_spacing},   {"tilt_rate_deg_s", s.tilt_rate},
                  {"tilt_start_step", settle_steps},    {"max_angle_deg", s.max_angle},
                  {"record_steps", record_steps},       {"onset_distance_m", s.onset_distance},
                  {"speed_angle_deg", s.speed_angle},   {"stop_distance_m", s.stop_distance},
                  {"gravity_m_s2", m.gravity}};
  w.experiment["analysed"] = observable_names(m_config);
  return w;
}

}  // namespace

std::unique_ptr<CaseDraft> draft_case(const StudyConfig& config, std::uint64_t assembly_seed) {
  return std::make_unique<InclineDraft>(config, assembly_seed);
}

}  // namespace demsa::experiments::incline

namespace demsa::experiments::incline {

// The schedule of incline.liggghts: settle_steps on the level plate, then records of record_steps up to max_angle,
// every probe present until it leaves (the cap: the tilt ends once every probe has left, case.cpp above).
CaseCost case_cost(const StudyConfig& config, const nlohmann::json& case_json, const fs::path& file,
                   const nlohmann::json& /*probed*/) {
  const InclineSettings& s = settings(config);
  const std::optional<double> dt = case_number(case_json, file, "dt", 0.0, 1.0);
  if (!dt || *dt <= 0.0) throw util::UserError(fmt::format("{}: no time step (dt)", file.string()));
  const long settle_steps = steps_for(s.settle_time, *dt, "[incline] settle_time");
  const long record_steps = steps_for(s.record_angle / s.tilt_rate, *dt, "[incline] record_angle / tilt_rate");
  const long records =
      static_cast<long>(std::ceil(s.max_angle / (s.tilt_rate * static_cast<double>(record_steps) * *dt) - 1e-9));
  const long atoms = s.rolling_probes + s.sliding_probes;
  CaseCost cost;
  cost.steps = settle_steps + records * record_steps;
  cost.particles = atoms;
  cost.atom_steps = static_cast<double>(cost.steps) * static_cast<double>(atoms);
  cost.may_end_early = true;
  cost.schedule = fmt::format(
      "{} probes for {} settling steps and up to {} records of {} steps (the cap: the tilt "
      "ends when every probe has left)",
      atoms, settle_steps, records, record_steps);
  return cost;
}

}  // namespace demsa::experiments::incline
