# FindMETIS
# ---------
# Finds the METIS graph partitioning library and creates the imported target METIS::METIS.
# Honours METIS_ROOT (CMake variable or environment). Sets METIS_FOUND, METIS_INCLUDE_DIR,
# METIS_LIBRARY and METIS_IDXTYPEWIDTH (32 or 64, read from metis.h).
find_path(METIS_INCLUDE_DIR NAMES metis.h
  HINTS ${METIS_ROOT} ENV METIS_ROOT PATH_SUFFIXES include)
find_library(METIS_LIBRARY NAMES metis
  HINTS ${METIS_ROOT} ENV METIS_ROOT PATH_SUFFIXES lib lib64)

if(METIS_INCLUDE_DIR AND EXISTS "${METIS_INCLUDE_DIR}/metis.h")
  file(STRINGS "${METIS_INCLUDE_DIR}/metis.h" _metis_idx REGEX "^#define[ \t]+IDXTYPEWIDTH[ \t]+[0-9]+")
  string(REGEX REPLACE ".*IDXTYPEWIDTH[ \t]+([0-9]+).*" "\\1" METIS_IDXTYPEWIDTH "${_metis_idx}")
  file(STRINGS "${METIS_INCLUDE_DIR}/metis.h" _metis_real REGEX "^#define[ \t]+REALTYPEWIDTH[ \t]+[0-9]+")
  string(REGEX REPLACE ".*REALTYPEWIDTH[ \t]+([0-9]+).*" "\\1" METIS_REALTYPEWIDTH "${_metis_real}")
endif()

include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(METIS REQUIRED_VARS METIS_LIBRARY METIS_INCLUDE_DIR METIS_IDXTYPEWIDTH)

if(METIS_FOUND AND NOT TARGET METIS::METIS)
  add_library(METIS::METIS UNKNOWN IMPORTED)
  set_target_properties(METIS::METIS PROPERTIES
    IMPORTED_LOCATION "${METIS_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${METIS_INCLUDE_DIR}")
endif()
mark_as_advanced(METIS_INCLUDE_DIR METIS_LIBRARY)
