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

include("${CMAKE_CURRENT_LIST_DIR}/../cmake/script_steps.cmake")
logrid_require(run_gl_free.cmake SOURCE_DIR WORK_DIR)
if(NOT CONFIG)
  set(CONFIG Release)
endif()
if(NOT JOBS)
  set(JOBS 2)
endif()

# The scratch build is kept between runs (only reconfigured), so that a second run
# rebuilds only what changed; it starts afresh when the source tree moved.
set(build "${WORK_DIR}/build")
logrid_scratch_build("${build}" "${SOURCE_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")

set(configure_args -S "${SOURCE_DIR}" -B "${build}" "-DCMAKE_BUILD_TYPE=${CONFIG}"
    -DLOGRID_BUILD_GL=OFF -DLOGRID_BUILD_TESTS=ON -DLOGRID_BUILD_BENCHMARKS=OFF
    # No GL on this "machine": find_package(OpenGL) fails, pkg-config finds nothing.
    -DCMAKE_DISABLE_FIND_PACKAGE_OpenGL=ON -DPKG_CONFIG_EXECUTABLE=/nonexistent/pkg-config
    -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF)
logrid_tool_args(configure_args)
logrid_run_step(gl_free_build "configure with LOGRID_BUILD_GL=OFF"
                "${CMAKE_COMMAND}" ${configure_args})

# Nothing GL may have been configured.
foreach(folder zread integration samples)
  if(EXISTS "${build}/${folder}")
    message(FATAL_ERROR "gl_free_build: the GL-free configuration configured ${folder}/")
  endif()
endforeach()

logrid_run_step(gl_free_build "build core, cpu, bvh and unit_test"
                "${CMAKE_COMMAND}" --build "${build}"
                --config "${CONFIG}" --target unit_test --parallel ${JOBS})

set(exe "${build}/bin/unit_test")
if(NOT EXISTS "${exe}")
  set(exe "${build}/bin/${CONFIG}/unit_test")  # multi-configuration generators
endif()
logrid_run_step(gl_free_build "run unit_test" "${exe}" --gtest_brief=1)
string(REGEX MATCH "[0-9]+ tests?[^\n]*ran[^\n]*" ran "${step_output}")
message(NOTICE "gl_free_build: ${ran}")
