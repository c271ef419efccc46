# Runs at install time (cmake --install, cpack), included by the install(CODE) of
# TrueaxisInstall.cmake: the files whose place and content depend on the prefix installed to.
#   prefix /usr (the .deb):  /etc/trueaxis/…,  /lib/systemd/system/trueaxis-*.service
#   any other prefix P:      P/etc/trueaxis/…, P/lib/systemd/system/trueaxis-*.service
# The units run P/bin/trueaxis with the configuration in that etc folder. A configuration file that
# is already there is kept: it is the shop's own (the .deb marks them conffiles, dpkg asks).

if(CMAKE_INSTALL_PREFIX STREQUAL "/usr")
  set(confdir /etc/trueaxis)
  set(unitdir /lib/systemd/system)
else()
  set(confdir ${CMAKE_INSTALL_PREFIX}/etc/trueaxis)
  set(unitdir ${CMAKE_INSTALL_PREFIX}/lib/systemd/system)
endif()
foreach(var TRUEAXIS_BINDIR TRUEAXIS_DOCDIR)
  if(NOT IS_ABSOLUTE "${${var}}")
    set(${var} "${CMAKE_INSTALL_PREFIX}/${${var}}")
  endif()
endforeach()

foreach(file shop.toml terminal.toml server.env web.env)
  if(EXISTS "$ENV{DESTDIR}${confdir}/${file}")
    message(STATUS "Kept: $ENV{DESTDIR}${confdir}/${file} (the shipped one: ${TRUEAXIS_PACKAGING_DIR}/etc/${file})")
  else()
    file(INSTALL DESTINATION "${confdir}" TYPE FILE FILES "${TRUEAXIS_PACKAGING_DIR}/etc/${file}")
  endif()
endforeach()

set(TRUEAXIS_BIN "${TRUEAXIS_BINDIR}/trueaxis")
set(TRUEAXIS_CONFDIR "${confdir}")
# Staged per destination: two installs at once (a test, cpack) never share a generated unit.
string(MD5 staging "$ENV{DESTDIR}${CMAKE_INSTALL_PREFIX}")
set(staging "${TRUEAXIS_STAGING_DIR}/${staging}")
file(READ "${TRUEAXIS_PACKAGING_DIR}/systemd/service-common.conf" TRUEAXIS_SERVICE_COMMON)
string(STRIP "${TRUEAXIS_SERVICE_COMMON}" TRUEAXIS_SERVICE_COMMON)
foreach(unit trueaxis-server trueaxis-terminal trueaxis-web)
  file(READ "${TRUEAXIS_PACKAGING_DIR}/systemd/${unit}.service.in" template)
  file(CONFIGURE OUTPUT "${staging}/${unit}.service" CONTENT "${template}" @ONLY)
  file(INSTALL DESTINATION "${unitdir}" TYPE FILE FILES "${staging}/${unit}.service")
endforeach()
