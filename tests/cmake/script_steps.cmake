# What the scripted tests (cmake -P) share: their required arguments, one step run with
# its output shown when it fails, and the arguments that give a nested configure the
# test run's own generator, compiler and launcher. include() it from the script.

# logrid_require(<script> <var>...): stops unless every -D<var>=... was given.
function(logrid_require script)
  foreach(var IN LISTS ARGN)
    if(NOT DEFINED ${var})
      message(FATAL_ERROR "${script}: -D${var}=... is required")
    endif()
  endforeach()
endfunction()

# logrid_run_step(<test> <name> <command>...): runs the command; on failure prints the
# command and its output and stops. Sets step_output in the caller.
function(logrid_run_step test name)
  message(STATUS "${test}: ${name}")
  execute_process(COMMAND ${ARGN}
    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  if(NOT rc EQUAL 0)
    string(REPLACE ";" " " cmd "${ARGN}")
    # NOTICE prints the output as it is; FATAL_ERROR would re-wrap compiler messages.
    message(NOTICE "command: ${cmd}\n--- output of step '${name}' ---\n${out}--- end of output ---")
    message(FATAL_ERROR "${test}: step '${name}' failed (exit status ${rc})")
  endif()
  set(step_output "${out}" PARENT_SCOPE)
endfunction()

# logrid_tool_args(<list>): appends to <list> the configure arguments for the variables
# GENERATOR, MAKE_PROGRAM, CXX_COMPILER and COMPILER_LAUNCHER that are set.
function(logrid_tool_args list)
  set(args ${${list}})
  if(GENERATOR)
    list(APPEND args -G "${GENERATOR}")
  endif()
  if(MAKE_PROGRAM)
    list(APPEND args "-DCMAKE_MAKE_PROGRAM=${MAKE_PROGRAM}")
  endif()
  if(CXX_COMPILER)
    # The same compiler as logrid's build: its static libraries carry that ABI.
    list(APPEND args "-DCMAKE_CXX_COMPILER=${CXX_COMPILER}")
  endif()
  if(COMPILER_LAUNCHER)
    list(APPEND args "-DCMAKE_CXX_COMPILER_LAUNCHER=${COMPILER_LAUNCHER}")
  endif()
  set(${list} ${args} PARENT_SCOPE)
endfunction()

# logrid_scratch_build(<dir>): keeps a scratch build between runs (only reconfigured),
# starting it afresh when it was configured from another source tree.
function(logrid_scratch_build build source)
  if(EXISTS "${build}/CMakeCache.txt")
    file(STRINGS "${build}/CMakeCache.txt" home REGEX "^CMAKE_HOME_DIRECTORY:")
    if(NOT home STREQUAL "CMAKE_HOME_DIRECTORY:INTERNAL=${source}")
      file(REMOVE_RECURSE "${build}")
    endif()
  endif()
endfunction()
