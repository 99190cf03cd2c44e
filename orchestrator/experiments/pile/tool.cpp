// `demsa postprocess pile DUMP` (case_tool.hpp): the angle of repose and h_P of one pile dump (paper §3.3), as text or
// JSON, measured with the pedestal and the measurement settings its case.json records (dump_angle.hpp), as `demsa
// run` measured it; options given on the command line override them.
#include "orchestrator/experiments/pile/angle_json.hpp"
#include "orchestrator/experiments/pile/dump_angle.hpp"
#include "orchestrator/experiments/pile/pile.hpp"
#include "orchestrator/util/errors.hpp"

#include <fmt/core.h>

#include <stdexcept>

namespace demsa::experiments::pile {

namespace pp = demsa::postprocess;

namespace {

class PileTool final : public CaseTool {
 public:
  std::vector<ToolOption> options() override {
    using C = ToolCheck;
    const std::string from_case = "(default: the case's case.json, else this value)";
    std::vector<ToolOption> o;
    o.push_back(ToolOption("DUMP",
                           "Final pile dump, or a case folder holding pile_final.dump; a case.json beside the dump "
                           "gives the pedestal and the measurement settings of the case",
                           &m_dump)
                    .needed());
    o.push_back(ToolOption("--pedestal-radius", "Pedestal radius r_cy [m] " + from_case, &m_options.pedestal_radius)
                    .checked(C::positive())
                    .with_default());
    o.push_back(
        ToolOption("--pedestal-top", "z of the pedestal top [m] " + from_case, &m_options.pedestal_top).with_default());
    o.push_back(ToolOption("--axis-x", "x of the pile axis [m]", &m_options.axis_x).with_default());
    o.push_back(ToolOption("--axis-y", "y of the pile axis [m]", &m_options.axis_y).with_default());
    o.push_back(ToolOption("--type", "Atom type of the particles (0 = all atoms)", &m_options.particle_type)
                    .checked(C::non_negative())
                    .with_default());
    o.push_back(ToolOption("--directions", "Number of directions phi_N " + from_case, &m_options.directions)
                    .checked(C::range(1, 100000))
                    .with_default());
    o.push_back(ToolOption("--levels", "Number of height levels between --level-low and --level-high " + from_case,
                           &m_options.levels)
                    .checked(C::range(2, 100000))
                    .with_default());
    o.push_back(ToolOption("--level-low",
                           fmt::format("Lowest level as a fraction of h_P (default: {} for --estimator robust)",
                                       pp::k_robust_level_low),
                           &m_level_low)
                    .checked(C::range(0.0, 1.0))
                    .with_default());
    o.push_back(ToolOption("--level-high",
                           fmt::format("Highest level as a fraction of h_P (default: {} for --estimator robust)",
                                       pp::k_robust_level_high),
                           &m_level_high)
                    .checked(C::range(0.0, 1.0))
                    .with_default());
    o.push_back(ToolOption("--min-points", "Directions with fewer boundary points are skipped", &m_options.min_points)
                    .checked(C::range(2, 100000))
                    .with_default());
    o.push_back(ToolOption("--point", "Fitted point of a boundary particle: centre or surface", &m_point)
                    .checked(C::member({"surface", "centre", "center"}))
                    .with_default());
    o.push_back(ToolOption("--estimator",
                           "Angle estimator: paper (§3.3) or robust (Theil-Sen lines on surface points; default: the "
                           "case's case.json, else this value)",
                           &m_estimator)
                    .checked(C::member(pp::angle_estimator_names()))
                    .with_default());
    o.push_back(ToolOption("--target-angle", "Target angle for E_phi [deg]", &m_options.target_angle).with_default());
    o.push_back(
        ToolOption("--json", "Print the whole result (lines and boundary particles included) as JSON", &m_json));
    return o;
  }

  std::vector<std::pair<std::string, std::string>> message_names() const override {
    return {{"pedestal_radius", "--pedestal-radius"},
            {"pedestal_top", "--pedestal-top"},
            {"axis_x", "--axis-x"},
            {"axis_y", "--axis-y"},
            {"particle_type", "--type"},
            {"directions", "--directions"},
            {"levels", "--levels"},
            {"level_low", "--level-low"},
            {"level_high", "--level-high"},
            {"min_points", "--min-points"},
            {"target_angle", "--target-angle"}};
  }

  std::string run(const std::set<std::string>& given, const std::function<void(const std::string&)>& warn) override {
    // Levels given hold for either estimator (an end not given at its default, the paper's); without them each
    // estimator measures on its own band (PileAngleOptions leaves them unset).
    if (given.count("--level-low") > 0 || given.count("--level-high") > 0) {
      m_options.level_low = m_level_low;
      m_options.level_high = m_level_high;
    }
    try {
      m_options.validate();
    } catch (const std::invalid_argument& e) {
      throw util::UserError(e.what());
    }
    DumpAngleRequest request;
    request.dump = m_dump;
    request.chosen.options = m_options;
    request.chosen.options.point = pp::boundary_point_kind_from_string(m_point);
    request.chosen.options.estimator = pp::angle_estimator_from_string(m_estimator);
    request.chosen.pedestal_radius = given.count("--pedestal-radius") > 0;
    request.chosen.pedestal_top = given.count("--pedestal-top") > 0;
    request.chosen.directions = given.count("--directions") > 0;
    request.chosen.levels = given.count("--levels") > 0;
    request.chosen.estimator = given.count("--estimator") > 0;
    request.warn = warn;
    const DumpAngle measured = measure_dump_angle(request);
    const pp::PileAngleResult& r = measured.result;
    const pp::PileAngleOptions& options = measured.options;
    if (m_json) return angle_result_json(r, measured.dump.string(), measured.case_json).dump(2) + "\n";
    std::string text;
    text += fmt::format("dump                   {}\n", measured.dump.string());
    text += fmt::format("pedestal               radius {:.6g} m, top at z = {:.6g} m ({})\n", options.pedestal_radius,
                        options.pedestal_top, measured.case_json.empty() ? std::string("options") : measured.case_json);
    text += fmt::format("estimator              {}\n", pp::to_string(options.estimator));
    text += fmt::format("particles on pedestal  {} of {}\n", r.particles_on_pedestal, r.particles_total);
    text += fmt::format("pile height h_P        {:.6g} m\n", r.pile_height);
    text += fmt::format("levels                 {} between {:.4g} m and {:.4g} m above the pedestal top\n",
                        r.level_heights.size(), r.level_heights.front(), r.level_heights.back());
    text += fmt::format("directions used        {} of {}\n", r.directions_used, options.directions);
    text += fmt::format("angle of repose        {:.3f} deg (sd {:.3f}, range {:.3f} .. {:.3f})\n", r.angle, r.angle_sd,
                        r.angle_min, r.angle_max);
    text += fmt::format("E_phi vs {:.4g} deg     {:.4f} deg^2\n", options.target_angle, r.angle_error);
    return text;
  }

 private:
  std::string m_dump;
  pp::PileAngleOptions m_options;
  std::string m_point = "centre";
  std::string m_estimator = "paper";
  double m_level_low = pp::k_paper_level_low;    ///< --level-low
  double m_level_high = pp::k_paper_level_high;  ///< --level-high
  bool m_json = false;
};

}  // namespace

std::unique_ptr<CaseTool> make_case_tool() { return std::make_unique<PileTool>(); }

}  // namespace demsa::experiments::pile
