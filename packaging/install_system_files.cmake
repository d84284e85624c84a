# Runs at install time (cmake/SoccInstall.cmake), so the paths are those of THIS install:
# the default map_server configs in <etc>/socc and map_server's systemd unit in
# <prefix>/lib/systemd/system. As GNUInstallDirs does, prefix /usr puts <etc> at /etc (the .deb)
# and any other prefix at <prefix>/etc. file(INSTALL) honours DESTDIR and the install manifest.
if(CMAKE_INSTALL_PREFIX STREQUAL "/usr")
  set(SOCC_ETC_DIR /etc/socc)
else()
  set(SOCC_ETC_DIR ${CMAKE_INSTALL_PREFIX}/etc/socc)
endif()
file(INSTALL DESTINATION ${SOCC_ETC_DIR} TYPE FILE
     FILES ${SOCC_SOURCE_DIR}/map_server/config/server.yaml
           ${SOCC_SOURCE_DIR}/map_server/config/default.yaml)

set(SOCC_BIN_DIR ${CMAKE_INSTALL_PREFIX}/${SOCC_BINDIR})
# One file per destination: the package tests install and cpack the same build concurrently.
string(MD5 dest "$ENV{DESTDIR}${CMAKE_INSTALL_PREFIX}")
set(unit ${SOCC_BINARY_DIR}/packaging/unit-${dest}/socc-map-server.service)
configure_file(${SOCC_SOURCE_DIR}/packaging/socc-map-server.service.in ${unit} @ONLY)
file(INSTALL DESTINATION ${CMAKE_INSTALL_PREFIX}/lib/systemd/system TYPE FILE FILES ${unit})
