# The pkg-config test: installs a finished logrid build tree into a scratch prefix and
# builds the consumer's programs (tests/install/consumer) with nothing but a compiler and
# the flags pkg-config gives for the installed logrid.pc and logrid-core.pc, the way a
# Makefile-based application would:
#   * both modules report the project's version;
#   * logrid-core brings no GL dependency (no libepoxy, no libdl);
#   * main.cpp (core and bvh) is built with logrid-core's flags and run;
#   * gl_main.cpp (every GL library) is built with logrid's flags (linked, not run:
#     running needs a GL context).
#
#   cmake -DBINARY_DIR=<logrid build> -DCONSUMER_DIR=<tests/install/consumer>
#         -DWORK_DIR=<scratch dir> -DVERSION=<x.y.z> -DPKG_CONFIG=<pkg-config>
#         -DCXX_COMPILER=<compiler> [-DCONFIG=<build type>] [-DWITH_GL=ON|OFF]
#         -P run_pkgconfig.cmake
#
# Each step's command and output are printed when it fails.
cmake_minimum_required(VERSION 3.20)

include("${CMAKE_CURRENT_LIST_DIR}/../cmake/script_steps.cmake")
logrid_require(run_pkgconfig.cmake BINARY_DIR CONSUMER_DIR WORK_DIR VERSION PKG_CONFIG CXX_COMPILER)
if(NOT CONFIG)
  set(CONFIG Release)
endif()

set(prefix "${WORK_DIR}/prefix")
file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")

# run_step(<name> <command>...): runs the command; on failure stops with its output.
function(run_step name)
  message(STATUS "install_pkgconfig: ${name}")
  execute_process(COMMAND ${ARGN}
    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    string(REPLACE ";" " " cmd "${ARGN}")
    message(NOTICE "command: ${cmd}\n--- output of step '${name}' ---\n${out}${err}--- end of output ---")
    message(FATAL_ERROR "install_pkgconfig: step '${name}' failed (exit status ${rc})")
  endif()
  string(STRIP "${out}" out)
  set(step_output "${out}" PARENT_SCOPE)
endfunction()

run_step("install" "${CMAKE_COMMAND}" --install "${BINARY_DIR}" --prefix "${prefix}"
         --config "${CONFIG}")

file(GLOB_RECURSE pc_files "${prefix}/*/pkgconfig/logrid.pc")
list(LENGTH pc_files n)
if(NOT n EQUAL 1)
  message(FATAL_ERROR "install_pkgconfig: expected one logrid.pc under ${prefix}, found ${n}: ${pc_files}")
endif()
get_filename_component(pc_dir "${pc_files}" DIRECTORY)
if(NOT EXISTS "${pc_dir}/logrid-core.pc")
  message(FATAL_ERROR "install_pkgconfig: ${pc_dir} holds logrid.pc but not logrid-core.pc")
endif()

# The scratch prefix's modules first (before any installed logrid), relocated there: the
# files name the prefix logrid was configured with. epoxy.pc comes from the system.
set(ENV{PKG_CONFIG_PATH} "${pc_dir}")
set(pc "${PKG_CONFIG}" "--define-variable=prefix=${prefix}")

foreach(module logrid logrid-core)
  run_step("${module} version" ${pc} --modversion ${module})
  if(NOT step_output STREQUAL VERSION)
    message(FATAL_ERROR "install_pkgconfig: ${module}.pc says version '${step_output}', "
                        "the project is ${VERSION}")
  endif()
endforeach()

run_step("logrid-core flags" ${pc} --cflags --libs logrid-core)
set(core_flags "${step_output}")
if(core_flags MATCHES "epoxy|-ldl")
  message(FATAL_ERROR "install_pkgconfig: logrid-core (no GL) links GL dependencies: ${core_flags}")
endif()
string(FIND "${core_flags}" "-I${prefix}/include" at)
if(at EQUAL -1)
  message(FATAL_ERROR "install_pkgconfig: logrid-core's flags do not name the installed "
                      "headers (${prefix}/include): ${core_flags}")
endif()
separate_arguments(core_flags UNIX_COMMAND "${core_flags}")

set(std -std=c++17 -Wall -Wextra -Werror)
run_step("build consumer_core" "${CXX_COMPILER}" ${std} "${CONSUMER_DIR}/main.cpp" ${core_flags}
         -o "${WORK_DIR}/consumer_core")
run_step("run consumer_core" "${WORK_DIR}/consumer_core")
message(NOTICE "${step_output}")

if(WITH_GL)
  run_step("logrid flags" ${pc} --cflags --libs logrid)
  set(gl_flags "${step_output}")
  separate_arguments(gl_flags UNIX_COMMAND "${gl_flags}")
  run_step("build consumer_gl" "${CXX_COMPILER}" ${std} "${CONSUMER_DIR}/gl_main.cpp" ${gl_flags}
           -o "${WORK_DIR}/consumer_gl")
  run_step("run consumer_gl (no context)" "${WORK_DIR}/consumer_gl")
  message(NOTICE "${step_output}")
endif()
