# Helpers shared by every logrid target: warnings, sanitizers, C++17.

function(logrid_configure_target target)
  target_compile_features(${target} PUBLIC cxx_std_17)
  set_target_properties(${target} PROPERTIES CXX_EXTENSIONS OFF)
  if(CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang")
    target_compile_options(${target} PRIVATE -Wall -Wextra -Wshadow -Wconversion)
    if(LOGRID_WERROR)
      target_compile_options(${target} PRIVATE -Werror)
    endif()
    if(LOGRID_SANITIZE)
      string(REPLACE ";" "," _san "${LOGRID_SANITIZE}")
      target_compile_options(${target} PRIVATE -fsanitize=${_san} -fno-omit-frame-pointer)
      target_link_options(${target} PUBLIC -fsanitize=${_san})
    endif()
  endif()
endfunction()

# A library of the project: alias logrid::<name>, headers under include/, exported.
function(logrid_add_library target alias)
  add_library(${target} ${ARGN})
  add_library(logrid::${alias} ALIAS ${target})
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${alias} OUTPUT_NAME logrid_${alias}
                                             POSITION_INDEPENDENT_CODE ON)
  target_include_directories(${target} PUBLIC
    $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  logrid_configure_target(${target})
  if(NOT LOGRID_EXCEPTIONS AND CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang")
    # Nothing in the libraries throws or catches (logrid/error.hpp): they build without.
    target_compile_options(${target} PRIVATE -fno-exceptions)
  endif()
  install(TARGETS ${target} EXPORT logridTargets
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
    LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
    RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  install(DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endfunction()
