# socc_add_lcmtypes(<target> <dir>): runs lcm-gen on <dir>/*.lcm at build time.
# Creates an INTERFACE target with the generated C++ headers (#include <socc/xxx_t.hpp>)
# and, when javac and lcm.jar are present, <target>_jar building lcmtypes/socc_lcmtypes.jar
# for lcm-spy (part of ALL).
function(socc_add_lcmtypes target dir)
  file(GLOB lcm_files CONFIGURE_DEPENDS ${dir}/*.lcm)
  set(out ${CMAKE_BINARY_DIR}/lcmtypes)
  set(hpps)
  foreach(f ${lcm_files})
    get_filename_component(name ${f} NAME_WE)
    list(APPEND hpps ${out}/cpp/socc/${name}.hpp)
  endforeach()
  add_custom_command(
    OUTPUT ${hpps}
    COMMAND ${CMAKE_COMMAND} -E make_directory ${out}/cpp
    COMMAND ${LCM_GEN_EXECUTABLE} --cpp --cpp-hpath ${out}/cpp ${lcm_files}
    COMMAND ${CMAKE_COMMAND} -P ${CMAKE_CURRENT_FUNCTION_LIST_DIR}/PatchLcmDecode.cmake ${hpps}
    DEPENDS ${lcm_files} ${CMAKE_CURRENT_FUNCTION_LIST_DIR}/PatchLcmDecode.cmake
    COMMENT "lcm-gen C++ types"
    VERBATIM)
  add_custom_target(${target}_gen DEPENDS ${hpps})
  add_library(${target} INTERFACE)
  add_dependencies(${target} ${target}_gen)
  target_include_directories(${target} SYSTEM INTERFACE $<BUILD_INTERFACE:${out}/cpp>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_link_libraries(${target} INTERFACE lcm::lcm)

  find_package(Java COMPONENTS Development QUIET)
  if(Java_JAVAC_EXECUTABLE AND Java_JAR_EXECUTABLE AND LCM_JAR)
    set(jar ${out}/socc_lcmtypes.jar)
    add_custom_command(
      OUTPUT ${jar}
      COMMAND ${CMAKE_COMMAND} -E rm -rf ${out}/java ${out}/classes
      COMMAND ${CMAKE_COMMAND} -E make_directory ${out}/java ${out}/classes
      COMMAND ${LCM_GEN_EXECUTABLE} --java --jpath ${out}/java ${lcm_files}
      COMMAND sh -c "${Java_JAVAC_EXECUTABLE} -nowarn -cp ${LCM_JAR} -d ${out}/classes ${out}/java/socc/*.java"
      COMMAND ${Java_JAR_EXECUTABLE} cf ${jar} -C ${out}/classes .
      DEPENDS ${lcm_files}
      COMMENT "lcm-gen Java types -> socc_lcmtypes.jar (for lcm-spy)"
      VERBATIM)
    add_custom_target(${target}_jar ALL DEPENDS ${jar})
    set(SOCC_LCMTYPES_JAR ${jar} PARENT_SCOPE)
  else()
    message(STATUS "javac or lcm.jar not found: no socc_lcmtypes.jar for lcm-spy")
  endif()
endfunction()
