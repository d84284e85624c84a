# Install rules, the CMake package `socc` and socc.pc (issue 17). Destinations are relative
# (GNUInstallDirs), so `cmake --install BUILD --prefix ANY` and CPack relocate everything.
# The package exports only what a client of the map service needs: socc::rpc (MapClient),
# socc::shared (pose conversion, labels, channels), socc::lcmtypes (generated types) and
# socc::auth, which socc::rpc links inside (static libraries: link-only, no public headers).
include(CMakePackageConfigHelpers)
set(SOCC_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/socc)
set(SOCC_DATA_DIR ${CMAKE_INSTALL_DATADIR}/socc)

install(TARGETS map_server odom_client socc-cli socc-eval socc-sim socc-to-lcmlog socc-loadtest
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
# The ROS 1 bag reader's child process, found beside the programs (bin/../libexec/socc/).
install(TARGETS socc-ros1-bag-reader RUNTIME DESTINATION ${CMAKE_INSTALL_LIBEXECDIR}/socc)

set(_socc_exported socc_lcmtypes socc_shared socc_auth socc_rpc)
foreach(t ${_socc_exported})
  string(REPLACE "socc_" "" _name ${t})
  set_target_properties(${t} PROPERTIES EXPORT_NAME ${_name})
endforeach()
# A sanitized build's static libraries need the sanitizer runtime in every program linking them.
if(SOCC_SANITIZE)
  set_property(TARGET socc_shared APPEND PROPERTY INTERFACE_LINK_OPTIONS
               $<INSTALL_INTERFACE:-fsanitize=address,undefined>)
endif()
install(TARGETS ${_socc_exported} EXPORT socc-targets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(EXPORT socc-targets NAMESPACE socc:: DESTINATION ${SOCC_CMAKE_DIR})

# Public headers: the map client and what it includes, plus the generated LCM types.
set(_inc ${PROJECT_SOURCE_DIR}/shared/include/socc)
install(FILES ${_inc}/channels.hpp ${_inc}/gravity_reference.hpp ${_inc}/labels.hpp ${_inc}/lcm_url.hpp
              ${_inc}/point_cloud.hpp
              ${_inc}/pose_conversion.hpp ${PROJECT_BINARY_DIR}/shared/include/socc/version.hpp
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/socc)
install(FILES ${_inc}/rpc/map_client.hpp ${_inc}/rpc/status_names.hpp ${_inc}/rpc/client_id.hpp
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/socc/rpc)
install(DIRECTORY ${PROJECT_BINARY_DIR}/lcmtypes/cpp/socc DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
        FILES_MATCHING PATTERN "*.hpp")

include(SoccDependencies)
socc_exported_dependencies("${_socc_exported}" SOCC_FIND_DEPENDENCIES SOCC_PC_REQUIRES SOCC_PC_LIBS)
configure_package_config_file(${PROJECT_SOURCE_DIR}/packaging/soccConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/packaging/soccConfig.cmake
                              INSTALL_DESTINATION ${SOCC_CMAKE_DIR} PATH_VARS SOCC_DATA_DIR)
write_basic_package_version_file(${PROJECT_BINARY_DIR}/packaging/soccConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/packaging/soccConfig.cmake
              ${PROJECT_BINARY_DIR}/packaging/soccConfigVersion.cmake
              ${PROJECT_SOURCE_DIR}/cmake/FindLCM.cmake
        DESTINATION ${SOCC_CMAKE_DIR})
# socc.pc finds its prefix relative to itself (${pcfiledir}): relocatable like the rest.
file(RELATIVE_PATH SOCC_PC_TO_PREFIX /p/${CMAKE_INSTALL_LIBDIR}/pkgconfig /p)
configure_file(${PROJECT_SOURCE_DIR}/packaging/socc.pc.in ${PROJECT_BINARY_DIR}/packaging/socc.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/packaging/socc.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)

# Data: the wire contract, the lcm-spy jar, default configs, socc-eval's gnuplot scripts.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/lcmtypes/ DESTINATION ${SOCC_DATA_DIR}/lcmtypes
        FILES_MATCHING PATTERN "*.lcm")
if(SOCC_LCMTYPES_JAR)
  install(FILES ${SOCC_LCMTYPES_JAR} DESTINATION ${SOCC_DATA_DIR}/java)
endif()
install(FILES ${PROJECT_SOURCE_DIR}/map_server/config/server.yaml
              ${PROJECT_SOURCE_DIR}/map_server/config/default.yaml
        DESTINATION ${SOCC_DATA_DIR}/map_server)
install(FILES ${PROJECT_SOURCE_DIR}/odom_client/config/default.yaml
              ${PROJECT_SOURCE_DIR}/odom_client/config/baseline.yaml
              ${PROJECT_SOURCE_DIR}/odom_client/config/kitti.yaml
        DESTINATION ${SOCC_DATA_DIR}/odom_client)

# Manual pages made from each binary's --help and --version (help2man), so `man map_server`
# works where the package is installed.
find_program(SOCC_HELP2MAN help2man)
if(SOCC_HELP2MAN)
  set(_socc_pages)
  set(_socc_man_exes map_server odom_client socc-cli socc-eval socc-sim socc-to-lcmlog socc-loadtest)
  if(TARGET socc-view)
    list(APPEND _socc_man_exes socc-view)
  endif()
  foreach(exe ${_socc_man_exes})
    set(_page ${PROJECT_BINARY_DIR}/man/${exe}.1)
    add_custom_command(OUTPUT ${_page}
      COMMAND ${SOCC_HELP2MAN} --no-info --no-discard-stderr --name "${exe} (socc)"
              --output ${_page} $<TARGET_FILE:${exe}>
      DEPENDS ${exe} COMMENT "Manual page of ${exe}" VERBATIM)
    list(APPEND _socc_pages ${_page})
  endforeach()
  add_custom_target(socc_man_pages ALL DEPENDS ${_socc_pages})
  install(FILES ${_socc_pages} DESTINATION ${CMAKE_INSTALL_MANDIR}/man1)
endif()
file(GLOB _socc_gnuplot ${PROJECT_SOURCE_DIR}/scripts/plot_*.gp)
install(FILES ${_socc_gnuplot} DESTINATION ${SOCC_DATA_DIR}/scripts)
install(PROGRAMS ${PROJECT_SOURCE_DIR}/scripts/spy.sh DESTINATION ${CMAKE_INSTALL_BINDIR}
        RENAME socc-spy)
# LAN mode of the map_server unit: a drop-in the administrator copies to /etc (docs/fleet.md).
install(FILES ${PROJECT_SOURCE_DIR}/packaging/socc-map-server-lan.conf
        DESTINATION ${SOCC_DATA_DIR}/systemd)

# /etc/socc and the systemd unit depend on the prefix of the install itself (CPack's /usr, a
# staging --prefix), so they are written at install time (packaging/install_system_files.cmake).
install(CODE "set(SOCC_SOURCE_DIR \"${PROJECT_SOURCE_DIR}\")
              set(SOCC_BINARY_DIR \"${PROJECT_BINARY_DIR}\")
              set(SOCC_BINDIR \"${CMAKE_INSTALL_BINDIR}\")")
install(SCRIPT ${PROJECT_SOURCE_DIR}/packaging/install_system_files.cmake)
