#include "orchestrator/experiments/oedometer/oedometer.hpp"

#include "orchestrator/experiments/case_record.hpp"
#include "orchestrator/experiments/oedometer/driver.hpp"
#include "orchestrator/study/folder.hpp"
#include "orchestrator/util/errors.hpp"
#include "orchestrator/util/log.hpp"
#include "postprocess/error.hpp"
#include "postprocess/oedometer.hpp"
#include "postprocess/stl.hpp"

#include <fmt/core.h>

#include <charconv>
#include <cmath>
#include <limits>

// The oedometer's descriptor: its measurement (paper §4), observables, output checks, report section and ParaView
// surfaces. Its settings are in settings.cpp, its case in case.cpp, the trial-step plate loop in driver.cpp.
namespace demsa::experiments::oedometer {

using namespace demsa::study;

namespace fs = std::filesystem;
namespace pp = demsa::postprocess;

// settings.cpp and case.cpp
std::vector<Setting> oedometer_settings();
std::vector<SettingSection> oedometer_sections();
void check_oedometer(const StudyConfig& config, const SectionCheck& at);
std::unique_ptr<CaseDraft> draft_case(const StudyConfig& config, std::uint64_t assembly_seed);
std::vector<std::string> limit_violations(const StudyConfig& config, const Material& material,
                                          const TimestepChoice& timestep);
std::string driver_command(const StudyConfig& config);

namespace {

constexpr std::string_view k_settlement_prefix = "settlement_";
constexpr double k_nan = std::numeric_limits<double>::quiet_NaN();

}  // namespace

std::string settlement_name(std::size_t k) { return fmt::format("{}{}", k_settlement_prefix, k); }

std::optional<std::size_t> settlement_index(std::string_view name) {
  if (name.substr(0, k_settlement_prefix.size()) != k_settlement_prefix) return std::nullopt;
  const std::string_view digits = name.substr(k_settlement_prefix.size());
  std::size_t k = 0;
  const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), k);
  if (digits.empty() || error != std::errc{} || end != digits.data() + digits.size() || k == 0) return std::nullopt;
  return k;
}

namespace {

std::map<std::string, double> measure(const fs::path& folder, const nlohmann::json& case_json) {
  const fs::path file = folder / k_case_json;
  const std::optional<double> side = case_number(case_json, file, "oedometer.box_side_m", 1e-9, 1e3);
  if (!side) throw util::UserError(file.string(), 0, "records no oedometer.box_side_m (the box)");
  postprocess::OedometerOptions options;
  options.box_side = *side;
  if (const nlohmann::json* measured = case_json.contains("oedometer") && case_json["oedometer"].is_object() &&
                                               case_json["oedometer"].contains("measured_settlements_m")
                                           ? &case_json["oedometer"]["measured_settlements_m"]
                                           : nullptr) {
    if (!measured->is_array())
      throw util::UserError(file.string(), 0,
                            fmt::format("oedometer.measured_settlements_m = {}: not a list", measured->dump()));
    for (std::size_t i = 0; i < measured->size(); ++i)
      options.measured_settlements.push_back(
          *case_number(case_json, file, fmt::format("oedometer.measured_settlements_m.{}", i), -1e3, 1e3));
  }
  const std::vector<pp::PlateState> states = pp::read_plate_states(folder / k_plate_states);
  const pp::OedometerResult result = pp::measure_oedometer(states, options);
  std::map<std::string, double> values;
  for (std::size_t i = 0; i < result.settlements.size(); ++i) values[settlement_name(i + 1)] = result.settlements[i];
  if (result.settlement_error) values[std::string(k_settlement_error)] = *result.settlement_error;
  return values;
}

std::vector<Observable> observables(const StudyConfig& config) {
  const OedometerSettings& o = settings(config);
  std::vector<Observable> names;
  for (std::size_t i = 1; i < o.loads.size(); ++i)
    names.push_back({settlement_name(i), fmt::format("settlement s_{}", i), "mm", 1e3, "m"});
  if (!o.measured_settlements.empty())
    names.push_back({std::string(k_settlement_error), "settlement error E_0", "mm", 1e3, "m"});
  return names;
}

std::optional<Observable> describe(std::string_view name) {
  const std::string n(name);
  if (name == k_settlement_error) return Observable{n, "settlement error E_0", "mm", 1e3, "m"};
  if (const auto k = settlement_index(name)) return Observable{n, fmt::format("settlement s_{}", *k), "mm", 1e3, "m"};
  return std::nullopt;
}

/// A postprocess reader's complaint about `file`, named by its file name alone (the case folder is in the report).
std::string problem(const fs::path& file, const pp::ParseError& e) {
  const std::string name = file.filename().string();
  return e.line() > 0 ? fmt::format("{}:{}: {}", name, e.line(), e.message())
                      : fmt::format("{}: {}", name, e.message());
}

/// plate_states.txt (postprocess::read_plate_states) has a row per load and every row converged; a file missing or
/// malformed is a missing output.
std::optional<OutputProblem> check_outputs(const fs::path& folder, const StudyConfig& config) {
  const fs::path file = folder / k_plate_states;
  const std::size_t loads = settings(config).loads.size();
  std::error_code ec;
  if (!fs::exists(file, ec))
    return OutputProblem{FailureClass::missing_dump, fmt::format("{} is missing", file.filename().string())};
  std::vector<pp::PlateState> states;
  try {
    states = pp::read_plate_states(file);
  } catch (const pp::ParseError& e) {
    return OutputProblem{FailureClass::missing_dump, problem(file, e)};
  }
  // A load not reached in its cap is final: the retry of a run of 2026-12-04 (sample 16 of
  // examples/calibration/oedometer.toml) ended at the same plate force, 100.744576561563 N, to the last digit.
  for (const pp::PlateState& state : states)
    if (!state.converged)
      return OutputProblem{FailureClass::plate_not_converged,
                           fmt::format("load {} N not reached (plate force {} N)", state.load_N, state.force_N), true};
  if (states.empty())  // nothing to measure
    return OutputProblem{FailureClass::plate_not_converged,
                         fmt::format("{} has no load step", file.filename().string())};
  if (states.size() < loads)
    return OutputProblem{FailureClass::plate_not_converged,
                         fmt::format("only {} of {} load steps reached", states.size(), loads)};
  return std::nullopt;
}

/// The settlement at each load after the first (not the error E_0, which is computed from them).
std::vector<std::string> lab_observables(const StudyConfig& config) {
  std::vector<std::string> names;
  for (std::size_t i = 1; i < settings(config).loads.size(); ++i) names.push_back(settlement_name(i));
  return names;
}

std::vector<std::pair<std::string, double>> default_targets(const StudyConfig& config) {
  const OedometerSettings& o = settings(config);
  const std::vector<double>& measured = o.measured_settlements;
  if (measured.empty())
    throw util::UserError(
        fmt::format("{}: no CalibrateOptions.targets given and the study has no [oedometer] measured_settlements; give "
                    "e.g. CalibrateOptions.targets settlement=0.5e-3,1.2e-3,1.9e-3",
                    config.file.string()));
  // Either n-1 values (loads after the first) or n values starting with the first load's 0.
  std::vector<std::pair<std::string, double>> targets;
  const std::size_t offset = measured.size() == o.loads.size() ? 1 : 0;
  for (std::size_t i = offset; i < measured.size(); ++i)
    targets.emplace_back(settlement_name(i + 1 - offset), measured[i]);
  return targets;
}

ReportFocus report_focus(const StudyConfig& config) {
  const OedometerSettings& o = settings(config);
  if (!o.measured_settlements.empty()) return {std::string(k_settlement_error), 0.0};
  return {settlement_name(o.loads.size() - 1), std::nullopt};
}

CaseReport case_report(const fs::path& folder, const std::string&, int sample, const StudyConfig& config) {
  const OedometerSettings& o = settings(config);
  CaseReport section;
  section.heading = fmt::format("Sample {}: the oedometer (paper Figs. 5 and 6b)", sample);
  const std::vector<postprocess::PlateState> states = postprocess::read_plate_states(folder / k_plate_states);
  postprocess::OedometerOptions options;
  options.box_side = o.box_side;
  options.measured_settlements = o.measured_settlements;
  const postprocess::OedometerResult r = postprocess::measure_oedometer(states, options);

  SettlementCurve curve;
  curve.title = fmt::format("sample {}: settlement against vertical stress", sample);
  curve.area = options.box_side * options.box_side;
  for (const postprocess::OedometerStep& step : r.steps) {
    curve.loads.push_back(step.load_N);
    curve.simulated.push_back(step.settlement_m);
  }
  const std::vector<double>& measured = o.measured_settlements;
  if (!measured.empty()) {
    curve.measured.assign(curve.loads.size(), k_nan);
    const size_t offset = measured.size() == o.loads.size() ? 0 : 1;
    if (!curve.measured.empty()) curve.measured[0] = 0.0;
    for (size_t i = 0; i < measured.size() && i + offset < curve.measured.size(); ++i)
      curve.measured[i + offset] = measured[i];
  }
  CaseTable table;
  table.caption = "Load steps: plate force and settlement relative to the first load";
  table.header = {"load L_n [N]", "stress [kPa]",      "plate force [N]",
                  "converged",    "settlement s [mm]", "measured s̃ [mm]"};
  for (size_t i = 0; i < r.steps.size(); ++i) {
    const postprocess::OedometerStep& st = r.steps[i];
    table.rows.push_back(
        {fmt::format("{:g}", st.load_N), fmt::format("{:.1f}", st.stress_Pa * 1e-3), fmt::format("{:.3f}", st.force_N),
         st.converged ? "yes" : "no", fmt::format("{:.4f}", st.settlement_m * 1e3),
         curve.measured.empty() || !std::isfinite(curve.measured[i]) ? ""
                                                                     : fmt::format("{:.4f}", curve.measured[i] * 1e3)});
  }
  section.tables.push_back(table);
  if (r.settlement_error)
    section.paragraphs.push_back(fmt::format("Settlement error E_0 = {:.4f} mm.", *r.settlement_error * 1e3));
  section.figures.push_back({fmt::format("Settlement of sample {} against the vertical stress, with the measured "
                                         "settlements; dashed: the load steps",
                                         sample),
                             "settlement_curve", curve});

  const fs::path history_file = folder / k_plate_history;
  if (fs::exists(history_file)) {
    const postprocess::PlateHistory h = postprocess::read_plate_history(history_file);
    if (h.size() > 0) {
      PlateHistoryPlot plot;
      plot.title = fmt::format("sample {}: plate iteration", sample);
      for (size_t i = 0; i < h.size(); ++i) {
        plot.step.push_back(static_cast<double>(h.step[i]));
        plot.load.push_back(h.load_N[i]);
        plot.force.push_back(h.force_N[i]);
        plot.plate_z.push_back(h.plate_z_m[i]);
      }
      section.figures.push_back({fmt::format("Force of the particles on the plate and plate height over the "
                                             "iteration of sample {}; dashed: the load step being applied",
                                             sample),
                                 "plate_history", plot});
    } else {
      section.notes.push_back(fmt::format("{}: no rows, no plate history plot", history_file.string()));
    }
  } else {
    section.notes.push_back(fmt::format("{}: missing, no plate history plot", history_file.string()));
  }
  return section;
}

/// The oedometer box (oedometer_box.liggghts: walls x, y = ±side/2, floor z = 0), drawn up to `height`: five quads,
/// counter-clockwise seen from inside.
pp::Surface open_box(double side, double height) {
  const double h = side / 2.0;
  pp::Surface s;
  s.points = {{-h, -h, 0.0},    {h, -h, 0.0},    {h, h, 0.0},    {-h, h, 0.0},
              {-h, -h, height}, {h, -h, height}, {h, h, height}, {-h, h, height}};
  s.polygons = {{0, 1, 2, 3}, {0, 4, 5, 1}, {1, 5, 6, 2}, {2, 6, 7, 3}, {3, 7, 4, 0}};
  return s;
}

std::vector<CaseSurface> vtk_surfaces(const fs::path& folder, const nlohmann::json& case_json, const pp::DumpFrame&) {
  const fs::path file = folder / k_case_json;
  const auto length = [&](const char* key) {
    const std::optional<double> v = case_number(case_json, file, fmt::format("oedometer.{}", key), 1e-9, 1e3);
    if (!v) throw util::UserError(file.string(), 0, fmt::format("has no oedometer.{} (the case's geometry)", key));
    return *v;
  };
  std::vector<CaseSurface> surfaces{{"box", open_box(length("box_side_m"), length("box_height_m"))}};
  const std::vector<pp::PlateState> states = pp::read_plate_states(folder / k_plate_states);
  if (states.empty()) {
    util::log::warn("{}: no load step in it yet, so no plate.vtp (the plate's height is not known)",
                    (folder / k_plate_states).string());
    surfaces.push_back({"plate", std::nullopt});
  } else {
    // plate.stl lies at z = 0; LIGGGHTS moves it to the plate height, and the last load state is where it stood
    // when the final dump was written.
    surfaces.push_back({"plate", pp::mesh_surface(pp::read_ascii_stl(folder / k_plate_stl), states.back().plate_z_m)});
  }
  return surfaces;
}

long particles(const StudyConfig& config) { return settings(config).particles; }
double largest_radius(const StudyConfig& config) { return settings(config).radii.r_max; }

}  // namespace

const Experiment& experiment() {
  static const Experiment descriptor{
      .name = "oedometer",
      .summary = "settlements, paper §4",
      .sections = oedometer_sections,
      .settings = oedometer_settings,
      .check = check_oedometer,
      .draft = draft_case,
      .limit_violations = limit_violations,
      .driver_command = driver_command,
      .drivers =
          [] {
            return std::vector<Driver>{
                {k_driver_command, "Run a trial-step oedometer case in-process", drive_oedometer}};
          },
      .particles = particles,
      .largest_radius = largest_radius,
      .final_dump = k_final_dump,
      .run_outputs =
          [] {
            return std::vector<std::string>{k_final_dump, k_plate_history, k_plate_states};
          },
      .measure = measure,
      .observables = observables,
      .describe = describe,
      .check_outputs = check_outputs,
      .default_targets = default_targets,
      .lab_observables = lab_observables,
      .report_focus = report_focus,
      .case_report = case_report,
      .vtk_surfaces = vtk_surfaces,
      .case_cost = case_cost,
      .probe_state = probe_state,
      .case_tool = {"Settlements, stress, void ratio and E_0 from the plate files (paper §4)", make_case_tool},
  };
  return descriptor;
}

}  // namespace demsa::experiments::oedometer
