# The install test: installs a finished logrid build tree into a scratch prefix, then
# configures, builds and runs the consumer project (tests/install/consumer) against it
# with find_package(logrid CONFIG), from scratch every time.
#
#   cmake -DBINARY_DIR=<logrid build> -DCONSUMER_DIR=<tests/install/consumer>
#         -DWORK_DIR=<scratch dir> [-DCONFIG=<build type>] [-DGENERATOR=<generator>]
#         [-DMAKE_PROGRAM=<ninja>] [-DCXX_COMPILER=<compiler>] -P run_consumer.cmake
#
# Each step's command and output are printed when it fails.
cmake_minimum_required(VERSION 3.20)

include("${CMAKE_CURRENT_LIST_DIR}/../cmake/script_steps.cmake")
logrid_require(run_consumer.cmake BINARY_DIR CONSUMER_DIR WORK_DIR)
if(NOT CONFIG)
  set(CONFIG Release)
endif()

set(prefix "${WORK_DIR}/prefix")
set(build "${WORK_DIR}/build")
file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")

logrid_run_step(install_consumer "install"
                "${CMAKE_COMMAND}" --install "${BINARY_DIR}" --prefix "${prefix}"
                --config "${CONFIG}")

set(configure_args -S "${CONSUMER_DIR}" -B "${build}" "-DCMAKE_PREFIX_PATH=${prefix}"
                   "-DCMAKE_BUILD_TYPE=${CONFIG}"
                   # Only the scratch prefix may satisfy find_package(logrid).
                   -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF)
logrid_tool_args(configure_args)
logrid_run_step(install_consumer "configure" "${CMAKE_COMMAND}" ${configure_args})

# The package must come from the scratch prefix, not from some other installed logrid.
file(STRINGS "${build}/CMakeCache.txt" found_dir REGEX "^logrid_DIR:")
string(REGEX REPLACE "^logrid_DIR:[A-Z]*=" "" found_dir "${found_dir}")
file(REAL_PATH "${prefix}" real_prefix)
file(REAL_PATH "${found_dir}" found_dir)
string(FIND "${found_dir}" "${real_prefix}/" at)
if(NOT at EQUAL 0)
  message(FATAL_ERROR "install_consumer: find_package(logrid) used '${found_dir}', "
                      "not the scratch prefix '${real_prefix}'\n${step_output}")
endif()

logrid_run_step(install_consumer "build" "${CMAKE_COMMAND}" --build "${build}" --config "${CONFIG}")

set(exe_dir "${build}")
if(NOT EXISTS "${exe_dir}/consumer_core")
  set(exe_dir "${build}/${CONFIG}")  # multi-configuration generators
endif()
logrid_run_step(install_consumer "run consumer_core" "${exe_dir}/consumer_core")
message(NOTICE "${step_output}")
logrid_run_step(install_consumer "run consumer_glm" "${exe_dir}/consumer_glm")
message(NOTICE "${step_output}")
logrid_run_step(install_consumer "run consumer_nothrow" "${exe_dir}/consumer_nothrow")
message(NOTICE "${step_output}")
