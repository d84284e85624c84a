# Finds LCM (Debian's liblcm-dev ships a pkg-config file but no CMake config).
# Provides the imported target lcm::lcm and the lcm-gen executable LCM_GEN_EXECUTABLE;
# installed with the socc CMake package, which asks only for COMPONENTS lib.
# LCM_JAR is set when liblcm-java is installed (for lcm-spy).
find_path(LCM_INCLUDE_DIR lcm/lcm-cpp.hpp)
find_library(LCM_LIBRARY NAMES lcm)
find_program(LCM_GEN_EXECUTABLE lcm-gen)
find_file(LCM_JAR lcm.jar PATHS /usr/share/java /usr/local/share/java)

include(FindPackageHandleStandardArgs)
# COMPONENTS lib (programs using the installed socc package) needs no lcm-gen.
set(_lcm_required LCM_LIBRARY LCM_INCLUDE_DIR)
if(NOT LCM_FIND_COMPONENTS OR "gen" IN_LIST LCM_FIND_COMPONENTS)
  list(APPEND _lcm_required LCM_GEN_EXECUTABLE)
endif()
find_package_handle_standard_args(LCM REQUIRED_VARS ${_lcm_required})

if(LCM_FOUND AND NOT TARGET lcm::lcm)
  add_library(lcm::lcm UNKNOWN IMPORTED)
  set_target_properties(lcm::lcm PROPERTIES
    IMPORTED_LOCATION "${LCM_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${LCM_INCLUDE_DIR}")
endif()
mark_as_advanced(LCM_INCLUDE_DIR LCM_LIBRARY LCM_GEN_EXECUTABLE LCM_JAR)
