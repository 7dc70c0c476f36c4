# The version test: installs a finished logrid build tree into a scratch prefix and asks
# find_package() for versions of it, from a scratch project, as a user's CMakeLists.txt
# would. logrid's version file (logridConfigVersion.cmake) declares SameMinorVersion
# compatibility, so for version X.Y.Z:
#   find_package(logrid X.Y)      found, with logrid_VERSION X.Y.Z;
#   find_package(logrid X.(Y+1))  refused (a later minor version);
#   find_package(logrid (X+1).0)  refused (a later major version);
#   find_package(logrid X.(Y-1))  refused when Y > 0 (before 1.0 a minor version breaks).
#
#   cmake -DBINARY_DIR=<logrid build> -DWORK_DIR=<scratch dir> -DVERSION=<x.y.z>
#         [-DCONFIG=<build type>] [-DGENERATOR=<generator>] [-DMAKE_PROGRAM=<ninja>]
#         [-DCXX_COMPILER=<compiler>] -P run_version.cmake
cmake_minimum_required(VERSION 3.20)

include("${CMAKE_CURRENT_LIST_DIR}/../cmake/script_steps.cmake")
logrid_require(run_version.cmake BINARY_DIR WORK_DIR VERSION)
if(NOT CONFIG)
  set(CONFIG Release)
endif()

set(prefix "${WORK_DIR}/prefix")
file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")

execute_process(COMMAND "${CMAKE_COMMAND}" --install "${BINARY_DIR}" --prefix "${prefix}"
                        --config "${CONFIG}"
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "install_version: cmake --install failed (exit status ${rc}):\n${out}")
endif()

string(REGEX MATCH "^([0-9]+)\\.([0-9]+)" _ "${VERSION}")
set(major ${CMAKE_MATCH_1})
set(minor ${CMAKE_MATCH_2})
math(EXPR next_minor "${minor} + 1")
math(EXPR next_major "${major} + 1")

# ask(<name> <requested version> <expect: found|refused>)
function(ask name requested expect)
  set(dir "${WORK_DIR}/${name}")
  file(MAKE_DIRECTORY "${dir}")
  file(WRITE "${dir}/CMakeLists.txt"
       "cmake_minimum_required(VERSION 3.20)\n"
       "project(logrid_version_${name} LANGUAGES CXX)\n"
       "find_package(logrid ${requested} CONFIG REQUIRED)\n"
       "message(STATUS \"logrid_VERSION=\${logrid_VERSION} logrid_DIR=\${logrid_DIR}\")\n")
  set(args -S "${dir}" -B "${dir}/build" "-DCMAKE_PREFIX_PATH=${prefix}"
           -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF)
  logrid_tool_args(args)
  execute_process(COMMAND "${CMAKE_COMMAND}" ${args}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  message(STATUS "install_version: find_package(logrid ${requested}): exit status ${rc}")
  if(expect STREQUAL "found")
    if(NOT rc EQUAL 0 OR NOT out MATCHES "logrid_VERSION=${VERSION} ")
      message(FATAL_ERROR "install_version: find_package(logrid ${requested}) should find "
                          "logrid ${VERSION} in ${prefix}:\n${out}")
    endif()
    file(REAL_PATH "${prefix}" real_prefix)
    string(REGEX MATCH "logrid_DIR=([^\n]*)" _ "${out}")
    file(REAL_PATH "${CMAKE_MATCH_1}" found_dir)
    string(FIND "${found_dir}" "${real_prefix}/" at)
    if(NOT at EQUAL 0)
      message(FATAL_ERROR "install_version: find_package(logrid ${requested}) used "
                          "'${found_dir}', not the scratch prefix '${real_prefix}'")
    endif()
  else()
    # Refused by the version file: CMake names the version it found and the one asked.
    if(rc EQUAL 0 OR NOT out MATCHES "version: ${VERSION}")
      message(FATAL_ERROR "install_version: find_package(logrid ${requested}) should refuse "
                          "logrid ${VERSION} (SameMinorVersion):\n${out}")
    endif()
  endif()
endfunction()

ask(same_minor "${major}.${minor}" found)
ask(next_minor "${major}.${next_minor}" refused)
ask(next_major "${next_major}.0" refused)
if(minor GREATER 0)
  math(EXPR previous_minor "${minor} - 1")
  ask(previous_minor "${major}.${previous_minor}" refused)
endif()
message(STATUS "install_version: logrid ${VERSION} found for ${major}.${minor}, refused for "
               "later (and earlier minor) versions")
