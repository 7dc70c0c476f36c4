# The GL-free build test: configures this source tree with -DLOGRID_BUILD_GL=OFF into a
# scratch directory on a machine that, as far as CMake can tell, has no GL at all (no
# OpenGL package, pkg-config finds nothing, so not libepoxy either), builds logrid::core,
# logrid::cpu, logrid::bvh and their unit tests, and runs those tests. It fails if any of
# them needs GL, at configure, build or run time (docs/DESIGN.md: log/ must build and be
# tested without any GL).
#
#   cmake -DSOURCE_DIR=<logrid source> -DWORK_DIR=<scratch dir> [-DCONFIG=<build type>]
#         [-DGENERATOR=<generator>] [-DMAKE_PROGRAM=<ninja>] [-DCXX_COMPILER=<compiler>]
#         [-DCOMPILER_LAUNCHER=<ccache>] [-DJOBS=<n>] -P run_gl_free.cmake
#
# Each step's command and output are printed when it fails.
cmake_minimum_required(VERSION 3.20)

foreach(var SOURCE_DIR WORK_DIR)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "run_gl_free.cmake: -D${var}=... is required")
  endif()
endforeach()
if(NOT CONFIG)
  set(CONFIG Release)
endif()
if(NOT JOBS)
  set(JOBS 2)
endif()

# The scratch build is kept between runs (only reconfigured), so that a second run
# rebuilds only what changed; it starts afresh when the source tree moved.
set(build "${WORK_DIR}/build")
if(EXISTS "${build}/CMakeCache.txt")
  file(STRINGS "${build}/CMakeCache.txt" home REGEX "^CMAKE_HOME_DIRECTORY:")
  if(NOT home STREQUAL "CMAKE_HOME_DIRECTORY:INTERNAL=${SOURCE_DIR}")
    file(REMOVE_RECURSE "${build}")
  endif()
endif()
file(MAKE_DIRECTORY "${WORK_DIR}")

# run_step(<name> <command>...): runs the command; on failure stops with its output.
function(run_step name)
  message(STATUS "gl_free_build: ${name}")
  execute_process(COMMAND ${ARGN}
    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  if(NOT rc EQUAL 0)
    string(REPLACE ";" " " cmd "${ARGN}")
    message(NOTICE "command: ${cmd}\n--- output of step '${name}' ---\n${out}--- end of output ---")
    message(FATAL_ERROR "gl_free_build: step '${name}' failed (exit status ${rc})")
  endif()
  set(step_output "${out}" PARENT_SCOPE)
endfunction()

set(configure_args -S "${SOURCE_DIR}" -B "${build}" "-DCMAKE_BUILD_TYPE=${CONFIG}"
    -DLOGRID_BUILD_GL=OFF -DLOGRID_BUILD_TESTS=ON -DLOGRID_BUILD_BENCHMARKS=OFF
    # No GL on this "machine": find_package(OpenGL) fails, pkg-config finds nothing.
    -DCMAKE_DISABLE_FIND_PACKAGE_OpenGL=ON -DPKG_CONFIG_EXECUTABLE=/nonexistent/pkg-config
    -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF)
if(GENERATOR)
  list(APPEND configure_args -G "${GENERATOR}")
endif()
if(MAKE_PROGRAM)
  list(APPEND configure_args "-DCMAKE_MAKE_PROGRAM=${MAKE_PROGRAM}")
endif()
if(CXX_COMPILER)
  list(APPEND configure_args "-DCMAKE_CXX_COMPILER=${CXX_COMPILER}")
endif()
if(COMPILER_LAUNCHER)
  list(APPEND configure_args "-DCMAKE_CXX_COMPILER_LAUNCHER=${COMPILER_LAUNCHER}")
endif()
run_step("configure with LOGRID_BUILD_GL=OFF" "${CMAKE_COMMAND}" ${configure_args})

# Nothing GL may have been configured.
foreach(folder zread integration samples)
  if(EXISTS "${build}/${folder}")
    message(FATAL_ERROR "gl_free_build: the GL-free configuration configured ${folder}/")
  endif()
endforeach()

run_step("build core, cpu, bvh and unit_test" "${CMAKE_COMMAND}" --build "${build}"
         --config "${CONFIG}" --target unit_test --parallel ${JOBS})

set(exe "${build}/bin/unit_test")
if(NOT EXISTS "${exe}")
  set(exe "${build}/bin/${CONFIG}/unit_test")  # multi-configuration generators
endif()
run_step("run unit_test" "${exe}" --gtest_brief=1)
string(REGEX MATCH "[0-9]+ tests?[^\n]*ran[^\n]*" ran "${step_output}")
message(NOTICE "gl_free_build: ${ran}")
