# trueaxis_requires_feature(<FEATURE>)
#   First line of the CMakeLists of a module, test folder or program that needs an optional
#   feature (cmake/TrueaxisDeps.cmake): without it the rest of that file is skipped.
macro(trueaxis_requires_feature feature)
  if(NOT TRUEAXIS_HAVE_${feature})
    return()
  endif()
endmacro()

# trueaxis_module(<name> [UNITY] [DEPS target...])
#   Builds src/<name>/*.cpp into the static library trueaxis_<name>, with the
#   public headers in include/trueaxis/<name>/, and records it so the CLI links it.
#   UNITY: the module's files compile in batches of 8 as one file each (CMake's UNITY_BUILD)
#   when TRUEAXIS_UNITY_BUILD is ON, saving the repeated parsing of the heavy headers; only for
#   modules whose files compile together (no two file-local helpers of the same name).
option(TRUEAXIS_UNITY_BUILD "Compile the modules marked UNITY in batches (faster from scratch)" ON)
function(trueaxis_module name)
  cmake_parse_arguments(ARG "UNITY" "" "DEPS" ${ARGN})
  file(GLOB sources CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/*.cpp)
  add_library(trueaxis_${name} STATIC ${sources})
  if(ARG_UNITY AND TRUEAXIS_UNITY_BUILD)
    set_target_properties(trueaxis_${name} PROPERTIES UNITY_BUILD ON UNITY_BUILD_BATCH_SIZE 8)
  endif()
  target_include_directories(trueaxis_${name} PUBLIC ${PROJECT_SOURCE_DIR}/include)
  target_compile_options(trueaxis_${name} PRIVATE -Wall -Wextra -Wno-unused-parameter -Wno-restrict)
  target_link_libraries(trueaxis_${name} PUBLIC ${ARG_DEPS})
  set_property(GLOBAL APPEND PROPERTY TRUEAXIS_MODULES trueaxis_${name})
endfunction()

# trueaxis_tests(<name> [DEPS target...])
#   Builds tests/<name>/*.cpp into the GoogleTest program test_<name> and
#   registers each test case with CTest. Tests find the shared data folder
#   and the CLI through compile definitions.
function(trueaxis_tests name)
  cmake_parse_arguments(ARG "" "" "DEPS" ${ARGN})
  file(GLOB sources CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/*.cpp)
  add_executable(test_${name} ${sources})
  target_link_libraries(test_${name} PRIVATE ${ARG_DEPS} GTest::gtest GTest::gmock GTest::gtest_main)
  # tests/support/: helpers shared by the suites (e.g. running the CLI).
  target_include_directories(test_${name} PRIVATE ${PROJECT_SOURCE_DIR}/tests)
  target_compile_definitions(test_${name} PRIVATE
    TRUEAXIS_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
    TRUEAXIS_SHARED_DATA_DIR="${PROJECT_SOURCE_DIR}/../shared/data"
    TRUEAXIS_CLI_PATH="$<TARGET_FILE:trueaxis>")
  add_dependencies(test_${name} trueaxis)
  gtest_discover_tests(test_${name}
    WORKING_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR}
    DISCOVERY_TIMEOUT 60
    PROPERTIES TIMEOUT 600)
endfunction()
