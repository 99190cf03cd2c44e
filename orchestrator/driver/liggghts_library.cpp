#include "orchestrator/driver/liggghts_library.hpp"

#include "orchestrator/util/errors.hpp"

#include <dlfcn.h>
#include <fmt/core.h>
#include <link.h>

#include <type_traits>

namespace demsa::driver {

namespace {

/// dlerror()'s text, or `fallback` when the loader gave none.
std::string loader_error(const char* fallback) {
  const char* e = dlerror();
  return e ? std::string(e) : std::string(fallback);
}

}  // namespace

LiggghtsLibrary load_liggghts_library(const std::string& library) {
  // RTLD_GLOBAL: Open MPI opens its components (MCA plugins) with dlopen, and they resolve libmpi's and
  // libopen-pal's symbols from the global scope (Open MPI FAQ, "building and running in a dlopen'ed library").
  void* handle = dlopen(library.c_str(), RTLD_NOW | RTLD_GLOBAL);
  if (!handle)
    throw util::UserError(fmt::format(
        "cannot load the LIGGGHTS library {} ({}); the trial-step oedometer runs LIGGGHTS inside demsa: install "
        "Debian's libliggghts3 (scripts/install-deps.sh), or for a build of scripts/build-liggghts.sh put its lib/ "
        "folder on LD_LIBRARY_PATH (run.sh of a `viscous` case does)",
        library, loader_error("not found")));
  LiggghtsLibrary lib;
  lib.path = library;
  link_map* map = nullptr;
  if (dlinfo(handle, RTLD_DI_LINKMAP, &map) == 0 && map && map->l_name && *map->l_name) lib.path = map->l_name;

  const auto resolve = [&](auto& entry, const char* name) {
    dlerror();
    void* symbol = dlsym(handle, name);
    if (!symbol)
      throw util::UserError(fmt::format("{}: no {} ({}): not LIGGGHTS's library interface with its MPI", lib.path, name,
                                        loader_error("null symbol")));
    entry = reinterpret_cast<std::remove_reference_t<decltype(entry)>>(symbol);
  };
  resolve(lib.open, "lammps_open");
  resolve(lib.close, "lammps_close");
  resolve(lib.file, "lammps_file");
  resolve(lib.command, "lammps_command");
  resolve(lib.extract_fix, "lammps_extract_fix");
  resolve(lib.extract_variable, "lammps_extract_variable");
  resolve(lib.mpi_init, "MPI_Init");
  resolve(lib.mpi_initialized, "MPI_Initialized");
  resolve(lib.mpi_finalize, "MPI_Finalize");
  resolve(lib.mpi_finalized, "MPI_Finalized");
  resolve(lib.mpi_comm_rank, "MPI_Comm_rank");
  // MPI_COMM_WORLD is a macro: `((MPI_Comm) &ompi_mpi_comm_world)` in Open MPI's mpi.h.
  dlerror();
  lib.comm_world = dlsym(handle, "ompi_mpi_comm_world");
  if (!lib.comm_world)
    throw util::UserError(fmt::format(
        "{}: LIGGGHTS is not built on Open MPI (no ompi_mpi_comm_world); demsa drive-oedometer knows Open MPI's "
        "MPI_COMM_WORLD only (Debian's LIGGGHTS and scripts/build-liggghts.sh use Open MPI)",
        lib.path));
  return lib;
}

}  // namespace demsa::driver
