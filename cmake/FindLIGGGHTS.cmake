# FindLIGGGHTS
# ------------
# Finds LIGGGHTS's library interface (Debian: libliggghts-dev, headers under /usr/include/liggghts) and the
# MPI it was built with (Debian: libopenmpi-dev; libliggghts-dev does not pull it in).
#
# Imported target:  LIGGGHTS::LIGGGHTS   (library.h, libliggghts, MPI C and C++ bindings)
# Variables:        LIGGGHTS_FOUND, LIGGGHTS_INCLUDE_DIR, LIGGGHTS_LIBRARY, LIGGGHTS_EXECUTABLE

find_path(LIGGGHTS_INCLUDE_DIR NAMES liggghts/library.h PATHS /usr/include /usr/local/include)
find_library(LIGGGHTS_LIBRARY NAMES liggghts)
find_program(LIGGGHTS_EXECUTABLE NAMES liggghts lmp_auto)

# MPI: libliggghts is linked against Open MPI; the C++ bindings (libmpi_cxx) are needed to link (see
# reference notes: plain -lmpi without -lmpi_cxx fails).
find_package(MPI QUIET COMPONENTS CXX)

include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(LIGGGHTS
  REQUIRED_VARS LIGGGHTS_LIBRARY LIGGGHTS_INCLUDE_DIR MPI_CXX_FOUND
  REASON_FAILURE_MESSAGE "install liggghts, libliggghts-dev and libopenmpi-dev (scripts/install-deps.sh)")

if(LIGGGHTS_FOUND AND NOT TARGET LIGGGHTS::LIGGGHTS)
  add_library(LIGGGHTS::LIGGGHTS UNKNOWN IMPORTED)
  set_target_properties(LIGGGHTS::LIGGGHTS PROPERTIES
    IMPORTED_LOCATION "${LIGGGHTS_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${LIGGGHTS_INCLUDE_DIR}")
  target_link_libraries(LIGGGHTS::LIGGGHTS INTERFACE MPI::MPI_CXX)
endif()
mark_as_advanced(LIGGGHTS_INCLUDE_DIR LIGGGHTS_LIBRARY LIGGGHTS_EXECUTABLE)
