// `demsa export-vtk CASE|DUMP [--out DIR]`: the final state of a case folder (particles, and the pedestal and ground
// of a pile or the box and plate of an oedometer), or the particles of the last frame of one dump file, as VTK XML
// PolyData that ParaView opens (exec/case_vtk.hpp, docs/how-to/case-by-hand.md "A case in ParaView"). Prints the files
// written.
#include "orchestrator/cli/commands.hpp"
#include "orchestrator/exec/case_vtk.hpp"
#include "orchestrator/study/folder.hpp"
#include "orchestrator/util/errors.hpp"

#include <fmt/core.h>

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace demsa::cli {

namespace fs = std::filesystem;

namespace {

struct ExportVtkArgs {
  std::string input;
  std::string out;
};

void run_export_vtk(const ExportVtkArgs& a) {
  const fs::path input(a.input);
  std::error_code ec;
  if (!fs::exists(input, ec)) throw util::UserError(a.input, 0, "no such case folder or dump file");
  std::vector<fs::path> written;
  if (fs::is_directory(input, ec)) {
    written = exec::write_case_vtk(input, a.out.empty() ? input / study::k_case_vtk_folder : fs::path(a.out));
  } else {
    // A bare dump: its particles only, as STEM.vtp beside it or in --out.
    const fs::path folder = a.out.empty() ? input.parent_path() : fs::path(a.out);
    const fs::path out = folder / (input.stem().string() + ".vtp");
    exec::write_dump_vtk(input, out);
    written.push_back(out);
  }
  for (const fs::path& p : written) fmt::print("{}\n", p.string());
}

}  // namespace

void register_export_vtk_command(CLI::App& app, CliState& state) {
  auto args = std::make_shared<ExportVtkArgs>();
  CLI::App* sub = app.add_subcommand(
      "export-vtk",
      "Write a case's final state (particles, pedestal/box/plate) or a dump's particles as VTK files for ParaView");
  sub->add_option("CASE_OR_DUMP", args->input,
                  "A case folder (its final dump and geometry; files go to CASE/vtk/) or a dump file (the "
                  "particles of its last frame; STEM.vtp beside it)")
      ->required();
  sub->add_option("--out", args->out, "Folder to write the .vtp files into instead");
  sub->callback([args, &state] {
    run_export_vtk(*args);
    state.exit_code = 0;
  });
}

}  // namespace demsa::cli
