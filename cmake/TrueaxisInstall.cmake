# What `cmake --install` puts where, and the Debian package (docs/install.md):
#   cmake --install build [--prefix P]     P/bin/trueaxis (+ trueaxis-hal* with LinuxCNC),
#                                           P/share/trueaxis/web, P/share/trueaxis/examples,
#                                           P/share/doc/trueaxis, P/etc/trueaxis, P/lib/systemd/system
#   cd build && cpack -G DEB                trueaxis_<version>_<arch>.deb (+ trueaxis-hal_…)
# The programs' own install() lines sit next to their targets (apps/trueaxis, src/linuxcnc). The
# program finds the pages and examples relative to itself (core/install_paths.hpp): any prefix works,
# and an installed tree can be moved as a whole.

set(TRUEAXIS_INSTALL_DATADIR ${CMAKE_INSTALL_DATADIR}/trueaxis)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/src/web/static/ DESTINATION ${TRUEAXIS_INSTALL_DATADIR}/web COMPONENT trueaxis)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/examples/ DESTINATION ${TRUEAXIS_INSTALL_DATADIR}/examples COMPONENT trueaxis)
# README.md beside docs/ keeps its links to docs/*.md working.
install(FILES ${PROJECT_SOURCE_DIR}/README.md DESTINATION ${CMAKE_INSTALL_DOCDIR} COMPONENT trueaxis)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/docs/ DESTINATION ${CMAKE_INSTALL_DOCDIR}/docs COMPONENT trueaxis)

# The configuration (/etc/trueaxis) and the systemd units depend on the prefix given at install time
# (`--prefix`, or /usr for the package): cmake/TrueaxisInstallSystemFiles.cmake runs then.
install(CODE "
  set(TRUEAXIS_PACKAGING_DIR \"${PROJECT_SOURCE_DIR}/packaging\")
  set(TRUEAXIS_STAGING_DIR \"${PROJECT_BINARY_DIR}/packaging\")
  set(TRUEAXIS_BINDIR \"${CMAKE_INSTALL_BINDIR}\")
  set(TRUEAXIS_DOCDIR \"${CMAKE_INSTALL_DOCDIR}\")
  include(\"${CMAKE_CURRENT_LIST_DIR}/TrueaxisInstallSystemFiles.cmake\")
" COMPONENT trueaxis)

# ---- The Debian package: `cpack -G DEB` in the build folder, after building. ----
# One package per component: trueaxis (everything above) and, when LinuxCNC's HAL was found,
# trueaxis-hal (the HAL programs: they need LinuxCNC's own libraries, which a shop without
# LinuxCNC does not want).
set(TRUEAXIS_DEB_MAINTAINER "trueaxis packagers <trueaxis@localhost>" CACHE STRING
    "Maintainer field of the Debian packages (cpack -G DEB)")
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME trueaxis)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "measure, model and compensate geometric and thermal errors of machine-tool axes")
# Installed with prefix /usr into a staging DESTDIR: /etc/trueaxis and /lib/systemd/system lie outside /usr.
set(CPACK_SET_DESTDIR ON)
set(CPACK_INSTALL_PREFIX /usr)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_STRIP_FILES ON)
set(CPACK_DEB_COMPONENT_INSTALL ON)
set(CPACK_COMPONENTS_ALL trueaxis)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_MAINTAINER "${TRUEAXIS_DEB_MAINTAINER}")
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)  # Depends: from the libraries the programs link (dpkg-shlibdeps)
set(CPACK_DEBIAN_TRUEAXIS_PACKAGE_NAME trueaxis)
set(CPACK_DEBIAN_TRUEAXIS_PACKAGE_DEPENDS "adduser, libjs-chart.js")  # the user in postinst; Chart.js for the pages
set(CPACK_DEBIAN_TRUEAXIS_PACKAGE_RECOMMENDS "systemd")
set(CPACK_COMPONENT_TRUEAXIS_DESCRIPTION "trueaxis measures, models and compensates the geometric and thermal\n\
errors of CNC machine-tool axes: ISO 230-2 analysis, model fitting, the real-time compensator,\n\
the workshop server, the machine terminal and the web front end, with systemd services for the\n\
server, the terminal and the web front end.")
set(CPACK_DEBIAN_TRUEAXIS_PACKAGE_CONTROL_EXTRA
    ${PROJECT_SOURCE_DIR}/packaging/debian/postinst ${PROJECT_SOURCE_DIR}/packaging/debian/prerm
    ${PROJECT_SOURCE_DIR}/packaging/debian/postrm ${PROJECT_SOURCE_DIR}/packaging/debian/conffiles)
set(CPACK_DEBIAN_TRUEAXIS_PACKAGE_CONTROL_STRICT_PERMISSION TRUE)
if(TARGET trueaxis-hal)
  list(APPEND CPACK_COMPONENTS_ALL hal)
  set(CPACK_DEBIAN_HAL_PACKAGE_NAME trueaxis-hal)
  set(CPACK_COMPONENT_HAL_DESCRIPTION "The LinuxCNC HAL programs of trueaxis: the HAL component trueaxis-hal\n\
and the virtual-machine plant trueaxis-hal-plant (docs/linuxcnc.md).")
endif()
# `cpack` packages what was built; it does not build everything (tests, benchmarks) first.
set(CMAKE_SKIP_INSTALL_ALL_DEPENDENCY ON)
include(CPack)
