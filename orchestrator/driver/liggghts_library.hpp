#pragma once
// LIGGGHTS's library interface (library.h) and the few MPI calls the trial-step driver makes, loaded at run time
// (dlopen, POSIX.1-2008) rather than linked: only `demsa drive-oedometer` needs them, and Debian's libliggghts
// brings VTK, Open MPI and some 45 other libraries that every demsa process would otherwise map and relocate at
// start (~40 ms each; docs/explanation/benchmarks.md, "Saltelli pipeline against OpenTURNS"). Loading it rather than
// moving the driver into a second executable keeps one binary: run.sh of a case finds one demsa ($DEMSA, the one that
// wrote it, or PATH), also when the folder moves to another machine, and nothing else has to be installed beside it.
//
// The library is found as the dynamic loader finds a linked one: LD_LIBRARY_PATH first (run.sh of a `viscous`
// case puts there the lib/ folder of the build of scripts/build-liggghts.sh it runs), then the system's
// (Debian's libliggghts3). So a case loads the library of the LIGGGHTS its study was checked against.
#include <string>

namespace demsa::driver {

/// The soname demsa loads (Debian's libliggghts3, and the library scripts/build-liggghts.sh builds).
inline constexpr const char* k_liggghts_soname = "libliggghts.so.3";

/// The loaded library: the entry points of library.h and of MPI (from the libmpi libliggghts is linked with).
/// Never unloaded (MPI and VTK register exit handlers inside their code).
struct LiggghtsLibrary {
  /// The file the dynamic loader opened for k_liggghts_soname.
  std::string path;
  /// MPI_COMM_WORLD of the library's MPI: Open MPI's `&ompi_mpi_comm_world` (MPI_Comm is a pointer there).
  void* comm_world = nullptr;

  int (*mpi_init)(int*, char***) = nullptr;
  int (*mpi_initialized)(int*) = nullptr;
  int (*mpi_finalize)() = nullptr;
  int (*mpi_finalized)(int*) = nullptr;
  int (*mpi_comm_rank)(void*, int*) = nullptr;

  void (*open)(int, char**, void*, void**) = nullptr;                      ///< lammps_open(argc, argv, MPI_Comm, &lmp)
  void (*close)(void*) = nullptr;                                          ///< lammps_close
  void (*file)(void*, const char*) = nullptr;                              ///< lammps_file
  char* (*command)(void*, const char*) = nullptr;                          ///< lammps_command
  void* (*extract_fix)(void*, const char*, int, int, int, int) = nullptr;  ///< lammps_extract_fix
  void* (*extract_variable)(void*, char*, char*) = nullptr;                ///< lammps_extract_variable
};

/// Loads `library` (a soname or a path; default k_liggghts_soname) with its MPI; loading it again only counts a
/// reference. Throws util::UserError naming the library and the loader's reason when it cannot be loaded, lacks an
/// entry point, or is built on an MPI other than Open MPI (the one Debian's LIGGGHTS and scripts/build-liggghts.sh
/// use; MPI_COMM_WORLD is implementation-defined).
LiggghtsLibrary load_liggghts_library(const std::string& library = k_liggghts_soname);

}  // namespace demsa::driver
