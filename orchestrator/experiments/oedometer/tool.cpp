// `demsa postprocess oedometer PLATEFILE...` (case_tool.hpp): settlements, stress, void ratio and E_0 of one case
// from its plate files (paper §4; plate_files.hpp), as text or JSON.
#include "orchestrator/experiments/oedometer/measurement_json.hpp"
#include "orchestrator/experiments/oedometer/oedometer.hpp"
#include "orchestrator/experiments/oedometer/plate_files.hpp"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

namespace demsa::experiments::oedometer {

namespace pp = demsa::postprocess;

namespace {

class OedometerTool final : public CaseTool {
 public:
  std::vector<ToolOption> options() override {
    using C = ToolCheck;
    std::vector<ToolOption> o;
    o.push_back(ToolOption("PLATEFILE", "plate_states.txt and/or plate_history.txt, or a case folder holding them",
                           &m_request.files)
                    .needed());
    o.push_back(ToolOption("--measured",
                           "Measured settlements [m] for the loads after the first (comma- or space-separated)",
                           &m_request.options.measured_settlements)
                    .split_at(','));
    o.push_back(ToolOption("--box-side", "Inner side of the square box [m]", &m_request.options.box_side)
                    .checked(C::positive())
                    .with_default());
    o.push_back(ToolOption("--floor-z", "z of the box floor [m]", &m_request.options.floor_z).with_default());
    o.push_back(
        ToolOption("--dump", "Dump whose type-1 particles give the solid volume for the void ratio", &m_request.dump));
    o.push_back(ToolOption("--load-tolerance", "Without plate_states.txt: |force - load| that counts as converged [N]",
                           &m_request.load_tolerance)
                    .checked(C::non_negative())
                    .with_default());
    o.push_back(ToolOption("--json", "Print the result (with the plate history) as JSON", &m_json));
    return o;
  }

  std::vector<std::pair<std::string, std::string>> message_names() const override {
    return {{"box_side", "--box-side"},
            {"floor_z", "--floor-z"},
            {"measured_settlements", "--measured"},
            {"solid_volume", "the solid volume of --dump"}};
  }

  std::string run(const std::set<std::string>&, const std::function<void(const std::string&)>&) override {
    const PlateFiles measured = measure_plate_files(m_request);
    const pp::OedometerResult& r = measured.result;
    if (m_json) {
      nlohmann::json j = measurement_json(r);
      j["states_file"] =
          measured.states_file ? nlohmann::json(measured.states_file->string()) : nlohmann::json(nullptr);
      j["dump"] = measured.dump_file ? nlohmann::json(measured.dump_file->string()) : nlohmann::json(nullptr);
      return j.dump(2) + "\n";
    }
    std::string text = fmt::format("load states from {}\n", measured.source);
    text += fmt::format("{:>10} {:>14} {:>12} {:>14} {:>12} {:>10} {}\n", "load_N", "plate_z_m", "force_N",
                        "settlement_m", "stress_Pa", "void_ratio", "converged");
    for (const pp::OedometerStep& s : r.steps)
      text += fmt::format("{:>10.6g} {:>14.8g} {:>12.6g} {:>14.6g} {:>12.6g} {:>10} {}\n", s.load_N, s.plate_z_m,
                          s.force_N, s.settlement_m, s.stress_Pa,
                          s.void_ratio ? fmt::format("{:.4f}", *s.void_ratio) : std::string("-"),
                          s.converged ? "yes" : "NO");
    if (r.settlement_error) text += fmt::format("E_0 = {:.6g} m\n", *r.settlement_error);
    if (r.history && !r.history->accepted.empty())
      text += fmt::format("trial steps: {} accepted, {} rejected\n", r.trials_accepted, r.trials_rejected);
    if (!r.all_converged) text += "warning: not every load step converged\n";
    return text;
  }

 private:
  PlateFilesRequest m_request;
  bool m_json = false;
};

}  // namespace

std::unique_ptr<CaseTool> make_case_tool() { return std::make_unique<OedometerTool>(); }

}  // namespace demsa::experiments::oedometer
