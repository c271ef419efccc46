# All third-party libraries come from Debian bookworm packages
# (scripts/install-deps.sh installs them).
#
# Core libraries: every build needs them (`scripts/install-deps.sh --demo` installs them).
find_package(PkgConfig REQUIRED)
find_package(Threads REQUIRED)
find_package(Eigen3 3.4 REQUIRED NO_MODULE)
find_package(nlohmann_json 3.10 REQUIRED)
find_package(fmt REQUIRED)
find_package(CLI11 REQUIRED)
find_package(tomlplusplus REQUIRED)
if(NOT TRUEAXIS_ONLY_HAL)
  pkg_check_modules(HTTPLIB REQUIRED IMPORTED_TARGET cpp-httplib)
endif()
find_package(SQLite3 REQUIRED)
pkg_check_modules(MODBUS REQUIRED IMPORTED_TARGET libmodbus)
pkg_check_modules(SODIUM REQUIRED IMPORTED_TARGET libsodium)
pkg_check_modules(XLSXWRITER REQUIRED IMPORTED_TARGET xlsxwriter)
pkg_check_modules(MINIZIP REQUIRED IMPORTED_TARGET minizip)
find_package(pugixml REQUIRED)
if(TRUEAXIS_BUILD_TESTS AND NOT TRUEAXIS_ONLY_HAL)
  find_package(GTest REQUIRED)
endif()
if(TRUEAXIS_BUILD_BENCH AND NOT TRUEAXIS_ONLY_HAL)
  find_package(benchmark REQUIRED)
endif()
# TRUEAXIS_ONLY_HAL (docs/linuxcnc.md "Install on a LinuxCNC machine"): the HAL programs and the
# modules they link, nothing else — LinuxCNC required, every other optional feature off, no
# cpp-httplib (only the workshop server and the web front end use it: their modules are left out),
# no GoogleTest/benchmark. The test linuxcnc.lean_configure checks what this configure asks for.
set(TRUEAXIS_HAL_SKIPPED_MODULES server web)

# Optional features (docs/building.md). Each TRUEAXIS_WITH_<NAME> is
#   AUTO (default): built when its library is found, else left out, said once here;
#   ON:  required, configuring fails naming the missing packages;
#   OFF: left out.
# TRUEAXIS_ALL_FEATURES=ON requires every feature whatever its own setting (scripts/test.sh:
# a missing package must fail the build, never skip tests silently).
# A feature left out removes its modules (trueaxis_module returns early when
# TRUEAXIS_HAVE_<NAME> is false), their tests, and its CLI commands, which then
# answer that this build lacks it (apps/trueaxis/optional_features.cpp).
option(TRUEAXIS_ALL_FEATURES "Require every optional feature (fail when a library is missing)" OFF)
set(TRUEAXIS_FEATURES VISION POSTGRES MQTT LINUXCNC)
set(TRUEAXIS_FEATURE_VISION_DOC "camera calibration, marker measurement, tool growth from images (OpenCV)")
set(TRUEAXIS_FEATURE_VISION_PACKAGES libopencv-core-dev libopencv-imgproc-dev libopencv-imgcodecs-dev libopencv-calib3d-dev)
set(TRUEAXIS_FEATURE_POSTGRES_DOC "history on a PostgreSQL server (libpqxx)")
set(TRUEAXIS_FEATURE_POSTGRES_PACKAGES libpqxx-dev)
set(TRUEAXIS_FEATURE_MQTT_DOC "live values on an MQTT broker (Eclipse Paho C++)")
set(TRUEAXIS_FEATURE_MQTT_PACKAGES libpaho-mqttpp-dev libpaho-mqtt-dev)
set(TRUEAXIS_FEATURE_LINUXCNC_DOC "LinuxCNC HAL component trueaxis-hal and its plant (hal.h, liblinuxcnchal)")
set(TRUEAXIS_FEATURE_LINUXCNC_PACKAGES "linuxcnc-uspace-dev (or -DTRUEAXIS_LINUXCNC_DIR=<LinuxCNC tree>)")

foreach(feature ${TRUEAXIS_FEATURES})
  set(TRUEAXIS_WITH_${feature} AUTO CACHE STRING "Build ${TRUEAXIS_FEATURE_${feature}_DOC}: AUTO, ON or OFF")
  set_property(CACHE TRUEAXIS_WITH_${feature} PROPERTY STRINGS AUTO ON OFF)
  string(TOUPPER "${TRUEAXIS_WITH_${feature}}" want)
  if(TRUEAXIS_ONLY_HAL)
    set(want OFF)
    if(feature STREQUAL "LINUXCNC")
      set(want ON)
    endif()
  elseif(TRUEAXIS_ALL_FEATURES)
    set(want ON)
  elseif(NOT want MATCHES "^(AUTO|ON|OFF)$")
    message(FATAL_ERROR "TRUEAXIS_WITH_${feature}='${TRUEAXIS_WITH_${feature}}': give AUTO, ON or OFF")
  endif()
  set(TRUEAXIS_WANT_${feature} ${want})
endforeach()

# Each check runs only when the feature is wanted. Nothing found is cached as "not found"
# for good: find_path/find_library/find_package search again while their result is NOTFOUND and
# pkg_check_modules while its _FOUND is false, so installing the packages and configuring again
# (scripts/test.sh after scripts/demo.sh) finds them.
set(found OFF)
if(NOT TRUEAXIS_WANT_VISION STREQUAL OFF)
  # Debian ships OpenCVConfig.cmake only in the big libopencv-dev; take it when present, else
  # find the four libraries directly.
  find_package(OpenCV QUIET COMPONENTS core imgproc imgcodecs calib3d)
  if(OpenCV_FOUND)
    set(TRUEAXIS_OPENCV_LIBS ${OpenCV_LIBS})
    set(TRUEAXIS_OPENCV_INCLUDE_DIRS ${OpenCV_INCLUDE_DIRS})
    set(found ON)
  else()
    find_path(TRUEAXIS_OPENCV_INCLUDE opencv2/core.hpp PATH_SUFFIXES opencv4)
    set(TRUEAXIS_OPENCV_LIBS)
    set(TRUEAXIS_OPENCV_INCLUDE_DIRS ${TRUEAXIS_OPENCV_INCLUDE})
    set(found ON)
    if(NOT TRUEAXIS_OPENCV_INCLUDE)
      set(found OFF)
    endif()
    foreach(c core imgproc imgcodecs calib3d)
      find_library(TRUEAXIS_OPENCV_${c} opencv_${c})
      if(NOT TRUEAXIS_OPENCV_${c})
        set(found OFF)
      endif()
      list(APPEND TRUEAXIS_OPENCV_LIBS ${TRUEAXIS_OPENCV_${c}})
    endforeach()
  endif()
endif()
set(TRUEAXIS_FOUND_VISION ${found})

set(found OFF)
if(NOT TRUEAXIS_WANT_POSTGRES STREQUAL OFF)
  pkg_check_modules(PQXX QUIET IMPORTED_TARGET GLOBAL libpqxx)  # libpqxx-dev 6.4
  set(found ${PQXX_FOUND})
endif()
set(TRUEAXIS_FOUND_POSTGRES ${found})

set(found OFF)
if(NOT TRUEAXIS_WANT_MQTT STREQUAL OFF)
  find_package(PahoMqttCpp QUIET)  # libpaho-mqttpp-dev 1.2
  if(PahoMqttCpp_FOUND)
    # Global, so the CLI and the tests, in other directories, can link through trueaxis_live.
    set_target_properties(PahoMqttCpp::paho-mqttpp3 PahoMqttC::PahoMqttC PROPERTIES IMPORTED_GLOBAL TRUE)
    set(found ON)
  endif()
endif()
set(TRUEAXIS_FOUND_MQTT ${found})

set(found OFF)
if(NOT TRUEAXIS_WANT_LINUXCNC STREQUAL OFF)
  # hal.h and liblinuxcnchal: from TRUEAXIS_LINUXCNC_DIR when given (a run-in-place tree — its
  # include/ and lib/ — or an installed prefix; defaults to $EMC2_HOME, which LinuxCNC's
  # scripts/rip-environment sets), else from LinuxCNC's pkg-config file when it has one, else
  # the packages' /usr/include/linuxcnc (docs/linuxcnc.md).
  set(TRUEAXIS_LINUXCNC_DIR "$ENV{EMC2_HOME}" CACHE PATH
      "LinuxCNC tree or prefix holding include/hal.h (or include/linuxcnc/hal.h) and lib/liblinuxcnchal.so")
  if(TRUEAXIS_LINUXCNC_DIR)
    find_path(LINUXCNC_HAL_INCLUDE_DIR hal.h PATHS ${TRUEAXIS_LINUXCNC_DIR}/include/linuxcnc
              ${TRUEAXIS_LINUXCNC_DIR}/include NO_DEFAULT_PATH)
    find_library(LINUXCNC_HAL_LIBRARY linuxcnchal PATHS ${TRUEAXIS_LINUXCNC_DIR}/lib NO_DEFAULT_PATH)
  else()
    pkg_check_modules(LINUXCNC_PC QUIET linuxcnc)
    find_path(LINUXCNC_HAL_INCLUDE_DIR hal.h HINTS ${LINUXCNC_PC_INCLUDE_DIRS}
              PATHS /usr/include/linuxcnc /usr/local/include/linuxcnc NO_DEFAULT_PATH)
    find_library(LINUXCNC_HAL_LIBRARY linuxcnchal HINTS ${LINUXCNC_PC_LIBRARY_DIRS})
  endif()
  if(LINUXCNC_HAL_INCLUDE_DIR AND LINUXCNC_HAL_LIBRARY)
    set(found ON)
    message(STATUS "LinuxCNC HAL: ${LINUXCNC_HAL_INCLUDE_DIR}/hal.h, ${LINUXCNC_HAL_LIBRARY}")
  endif()
endif()
set(TRUEAXIS_FOUND_LINUXCNC ${found})

# TRUEAXIS_FEATURE_DEFINITIONS: TRUEAXIS_HAVE_<NAME>=0/1 for the few files that ask (the CLI's
# apps/trueaxis/optional_features.cpp, tests/e2e).
set(TRUEAXIS_FEATURE_DEFINITIONS)
foreach(feature ${TRUEAXIS_FEATURES})
  if(TRUEAXIS_FOUND_${feature})
    set(TRUEAXIS_HAVE_${feature} ON)
    list(APPEND TRUEAXIS_FEATURE_DEFINITIONS TRUEAXIS_HAVE_${feature}=1)
    message(STATUS "trueaxis feature ${feature}: ON — ${TRUEAXIS_FEATURE_${feature}_DOC}")
  elseif(TRUEAXIS_WANT_${feature} STREQUAL ON)
    list(JOIN TRUEAXIS_FEATURE_${feature}_PACKAGES " " packages)
    message(FATAL_ERROR "trueaxis feature ${feature} (${TRUEAXIS_FEATURE_${feature}_DOC}) is required "
                        "(TRUEAXIS_WITH_${feature}=ON or TRUEAXIS_ALL_FEATURES=ON) but its library was not found: "
                        "install ${packages} (bash scripts/install-deps.sh --all) and configure again")
  else()
    set(TRUEAXIS_HAVE_${feature} OFF)
    list(APPEND TRUEAXIS_FEATURE_DEFINITIONS TRUEAXIS_HAVE_${feature}=0)
    if(TRUEAXIS_WANT_${feature} STREQUAL OFF)
      message(STATUS "trueaxis feature ${feature}: OFF (TRUEAXIS_WITH_${feature}=OFF)")
    else()
      message(STATUS "trueaxis feature ${feature}: OFF — library not found (bash scripts/install-deps.sh --all "
                     "installs it); its modules, tests and commands are left out")
    endif()
  endif()
endforeach()
unset(found)
