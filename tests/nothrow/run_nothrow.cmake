# The no-exceptions build test: configures this source tree with -DLOGRID_EXCEPTIONS=OFF
# into a scratch directory, builds the libraries (every one compiled with
# -fno-exceptions, checked in the compile commands), and runs the install test
# (tests/install/run_consumer.cmake) on that build: the consumer project, its
# -fno-exceptions program consumer_nothrow among them, against the installed libraries.
#
#   cmake -DSOURCE_DIR=<logrid source> -DWORK_DIR=<scratch dir> [-DCONFIG=<build type>]
#         [-DGENERATOR=<generator>] [-DMAKE_PROGRAM=<ninja>] [-DCXX_COMPILER=<compiler>]
#         [-DCOMPILER_LAUNCHER=<ccache>] [-DJOBS=<n>] -P run_nothrow.cmake
#
# Each step's command and output are printed when it fails.
cmake_minimum_required(VERSION 3.20)

include("${CMAKE_CURRENT_LIST_DIR}/../cmake/script_steps.cmake")
logrid_require(run_nothrow.cmake SOURCE_DIR WORK_DIR)
if(NOT CONFIG)
  set(CONFIG Release)
endif()
if(NOT JOBS)
  set(JOBS 2)
endif()

set(build "${WORK_DIR}/build")
logrid_scratch_build("${build}" "${SOURCE_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")

set(configure_args -S "${SOURCE_DIR}" -B "${build}" "-DCMAKE_BUILD_TYPE=${CONFIG}"
    -DLOGRID_EXCEPTIONS=OFF -DLOGRID_WERROR=ON -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF)
logrid_tool_args(configure_args)
logrid_run_step(nothrow_build "configure with LOGRID_EXCEPTIONS=OFF"
                "${CMAKE_COMMAND}" ${configure_args})
logrid_run_step(nothrow_build "build the libraries"
                "${CMAKE_COMMAND}" --build "${build}" --config "${CONFIG}"
                --parallel ${JOBS})

# Every library source was compiled with -fno-exceptions.
file(READ "${build}/compile_commands.json" commands)
string(JSON count LENGTH "${commands}")
math(EXPR last "${count} - 1")
set(sources 0)
foreach(i RANGE ${last})
  string(JSON command GET "${commands}" ${i} command)
  string(JSON file GET "${commands}" ${i} file)
  if(NOT command MATCHES "-fno-exceptions")
    message(FATAL_ERROR "nothrow_build: ${file} was compiled with exceptions:\n${command}")
  endif()
  math(EXPR sources "${sources} + 1")
endforeach()
message(NOTICE "nothrow_build: ${sources} library sources compiled with -fno-exceptions")

# And no library calls a throwing form: those are defined only where exceptions are
# (inline, under LOGRID_HAS_EXCEPTIONS), so such a call is a logrid symbol that the
# libraries use and none defines.
find_program(NM NAMES nm REQUIRED)
file(GLOB_RECURSE archives "${build}/*.a")
set(used "")
set(defined "")
foreach(archive IN LISTS archives)
  logrid_run_step(nothrow_build "symbols used by ${archive}"
                  "${NM}" -C --undefined-only "${archive}")
  string(REGEX MATCHALL "U logrid::[^\n]*" found "${step_output}")
  list(APPEND used ${found})
  logrid_run_step(nothrow_build "symbols defined in ${archive}"
                  "${NM}" -C --defined-only "${archive}")
  string(REGEX MATCHALL "[TWVu] logrid::[^\n]*" found "${step_output}")
  list(APPEND defined ${found})
endforeach()
list(TRANSFORM used REPLACE "^U " "")
list(TRANSFORM defined REPLACE "^[TWVu] " "")
list(REMOVE_DUPLICATES used)
list(REMOVE_ITEM used ${defined})
if(used)
  list(JOIN used "\n  " missing)
  message(FATAL_ERROR "nothrow_build: the libraries call what only a build with exceptions "
                      "defines (a throwing form?):\n  ${missing}")
endif()

logrid_run_step(nothrow_build "install and build the consumer against it"
                "${CMAKE_COMMAND}"
                "-DBINARY_DIR=${build}" "-DCONSUMER_DIR=${SOURCE_DIR}/tests/install/consumer"
                "-DWORK_DIR=${WORK_DIR}/consumer" "-DCONFIG=${CONFIG}" "-DGENERATOR=${GENERATOR}"
                "-DMAKE_PROGRAM=${MAKE_PROGRAM}" "-DCXX_COMPILER=${CXX_COMPILER}"
                -P "${SOURCE_DIR}/tests/install/run_consumer.cmake")
message(NOTICE "${step_output}")
