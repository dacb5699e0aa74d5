# `cmake --install build --prefix PREFIX`: the binaries into PREFIX/bin, config/ and maps/ into
# PREFIX/share/fleet (where the installed binaries look, core/common/paths.cpp), the systemd unit
# of fleet-server, and the README. `cpack -G DEB` in build/ packages the same tree for /usr.
install(TARGETS fleet-server fleet-agent fleetctl fleet-vda5050 RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/config/ DESTINATION ${CMAKE_INSTALL_DATADIR}/fleet/config)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/maps/ DESTINATION ${CMAKE_INSTALL_DATADIR}/fleet/maps
        FILES_MATCHING PATTERN "*.yaml" PATTERN "*.xodr" PATTERN "tools" EXCLUDE)
install(FILES ${PROJECT_SOURCE_DIR}/README.md DESTINATION ${CMAKE_INSTALL_DOCDIR})

# The unit names the installed fleet-server, so it is written at install time, when the prefix
# (the one given to --install, or /usr under cpack) is known.
install(CODE "
  set(unit \"\$ENV{DESTDIR}\${CMAKE_INSTALL_PREFIX}/lib/systemd/system/fleet-server.service\")
  message(STATUS \"Installing: \${unit}\")
  configure_file(\"${PROJECT_SOURCE_DIR}/packaging/fleet-server.service.in\" \"\${unit}\" @ONLY)
")

set(CPACK_PACKAGE_NAME fleet)
set(CPACK_PACKAGE_VENDOR "Fleet")
set(CPACK_PACKAGE_CONTACT "Fleet developers <fleet@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
    "Multi-fleet coordination server and simulated robot agents over Cyclone DDS")
set(CPACK_PACKAGE_DESCRIPTION
    "fleet-server routes transport orders, traffic grants and robot poses over Cyclone DDS to\n\
fleet-agent processes, one per simulated robot; fleetctl injects orders and runs demos and soaks.")
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION misc)
# The runtime dependencies are the packages of the shared libraries the binaries load
# (dpkg-shlibdeps, from dpkg-dev); useradd (passwd) is needed for the fleet user.
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_DEPENDS "passwd")
set(CPACK_DEBIAN_PACKAGE_CONTROL_EXTRA
    "${PROJECT_SOURCE_DIR}/packaging/postinst;${PROJECT_SOURCE_DIR}/packaging/prerm;${PROJECT_SOURCE_DIR}/packaging/postrm")
set(CPACK_DEBIAN_PACKAGE_CONTROL_STRICT_PERMISSION ON)
include(CPack)
