# CPack: `cpack -G DEB` in a build directory makes socc_<version>_<arch>.deb, installable with
# `apt install ./socc_*.deb`. Runtime dependencies come from dpkg-shlibdeps on the binaries
# (the Debian packages of their shared libraries); tests/package/deb_test.sh checks them.
set(CPACK_PACKAGE_NAME socc)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_VENDOR socc)
set(CPACK_PACKAGE_CONTACT "socc maintainers <socc@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
    "shared semantic occupancy map server and LiDAR odometry client over LCM")
set(CPACK_PACKAGE_DESCRIPTION
    "map_server, odom_client, socc-cli, socc-eval, socc-sim, socc-to-lcmlog and socc-loadtest, a
systemd unit for map_server, and the client library (CMake package socc, socc.pc).")
set(CPACK_GENERATOR DEB)
# /usr, with DESTDIR staging: the install-time paths (/etc/socc, the unit's ExecStart) are final.
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_INSTALL_PREFIX /usr)
set(CPACK_SET_DESTDIR ON)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
# Stripped binaries, as Debian ships them (about a third of the size; faster to pack and install).
set(CPACK_STRIP_FILES ON)
# Not linked, but used: socc-eval plots (gnuplot), socc-spy (lcm-spy: Java and lcm.jar);
# building against the package needs the headers of its dependencies.
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "gnuplot-nox")
set(CPACK_DEBIAN_PACKAGE_SUGGESTS
    "liblcm-bin, liblcm-java, default-jre-headless, liblcm-dev, libeigen3-dev, libssl-dev")
set(CPACK_DEBIAN_PACKAGE_CONTROL_EXTRA ${PROJECT_SOURCE_DIR}/packaging/conffiles)
include(CPack)
