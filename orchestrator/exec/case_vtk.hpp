#pragma once
// The final state of a case as files ParaView opens directly (docs/how-to/case-by-hand.md "A case in ParaView"): VTK
// XML PolyData (postprocess/vtk.hpp says why that format), written after a case is measured (runner, point_run) and by
// `demsa export-vtk`. Files, in CASE/vtk/ unless another folder is given:
//   particles.vtp  every atom of the final dump: id, type, radius, velocity
//   NAME.vtp       each surface of the case's experiment (Experiment::vtk_surfaces): for a pile pedestal.vtp (the
//                  mesh LIGGGHTS used) and ground.vtp; for an oedometer box.vtp and plate.vtp; ...
#include <filesystem>
#include <vector>

namespace demsa::exec {

inline constexpr const char* k_vtk_particles = "particles.vtp";

/// Writes the VTK files of the finished case in `case_dir` into `out_dir` (created when missing), each atomically;
/// returns them in the order above. Throws util::UserError when `case_dir` has no case.json or final dump, or its
/// case.json lacks a value the geometry needs (naming the file, the key and the value); postprocess::ParseError
/// (file:line) on a malformed dump, STL or plate file. A surface the case has no state of yet (an oedometer's plate
/// before its first load) is not written, and a file of it from an earlier state is removed.
std::vector<std::filesystem::path> write_case_vtk(const std::filesystem::path& case_dir,
                                                  const std::filesystem::path& out_dir);

/// Writes the particles of the last frame of `dump` to the file `out` atomically (postprocess::particles_vtp).
void write_dump_vtk(const std::filesystem::path& dump, const std::filesystem::path& out);

/// After a case was measured: write_case_vtk(case_dir, case_dir / study::k_case_vtk_folder). Any failure is a
/// warning naming the case, never an error: the case's observables do not depend on its pictures.
void write_case_vtk_or_warn(const std::filesystem::path& case_dir);

}  // namespace demsa::exec
