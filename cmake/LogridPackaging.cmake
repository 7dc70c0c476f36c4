# What an installed logrid offers besides its CMake package (logridConfig.cmake and
# logridConfigVersion.cmake, written by the top-level CMakeLists.txt): pkg-config files
# and a Debian package.
#
# pkg-config. Two modules, as the CMake package has components:
#   logrid-core  logrid::core, logrid::cpu and logrid::bvh: no GL;
#   logrid       everything that was built: logrid-core plus, with LOGRID_BUILD_GL,
#                logrid::zread and logrid::gl (they need libepoxy, which loads libEGL
#                and libGL at run time, and libdl).
# The libraries are static, so their dependencies are in Libs and Requires (not the
# .private fields): every consumer links them. The headers need C++17; pkg-config has no
# field for that (pass -std=c++17 where the compiler's default is older).
#   c++ -std=c++17 app.cpp $(pkg-config --cflags --libs logrid)
# The files name the prefix logrid was configured with (CMAKE_INSTALL_PREFIX); for an
# install elsewhere (cmake --install build --prefix DIR) pass
# --define-variable=prefix=DIR to pkg-config.
#
# Debian package (cpack -G DEB in the build directory): liblogrid-dev, the static
# libraries, headers, CMake package and pkg-config files, installed under
# CMAKE_INSTALL_PREFIX (configure with -DCMAKE_INSTALL_PREFIX=/usr for a Debian system;
# scripts/package-test.sh builds it that way and tests it in a fresh Debian 12 root).

# ---------------------------------------------------------------------------
# pkg-config files
# ---------------------------------------------------------------------------
foreach(kind LIBDIR INCLUDEDIR)
  if(IS_ABSOLUTE "${CMAKE_INSTALL_${kind}}")
    set(LOGRID_PC_${kind} "${CMAKE_INSTALL_${kind}}")
  else()
    set(LOGRID_PC_${kind} "\${prefix}/${CMAKE_INSTALL_${kind}}")
  endif()
endforeach()

# logrid::cpu's worker threads (Threads::Threads).
set(LOGRID_PC_CORE_LIBS "")
if(CMAKE_USE_PTHREADS_INIT)
  set(LOGRID_PC_CORE_LIBS "-pthread")
elseif(CMAKE_THREAD_LIBS_INIT)
  set(LOGRID_PC_CORE_LIBS "${CMAKE_THREAD_LIBS_INIT}")
endif()

# Linked in dependency order: gl before zread and bvh, zread before cpu, all before core.
if(LOGRID_BUILD_GL)
  set(LOGRID_PC_DESCRIPTION "with its GL depth sources and headless EGL context")
  set(LOGRID_PC_REQUIRES "logrid-core = ${PROJECT_VERSION}, epoxy")
  set(LOGRID_PC_LIBS "-L\${libdir} -llogrid_gl -llogrid_zread")
  foreach(lib IN LISTS CMAKE_DL_LIBS)
    string(APPEND LOGRID_PC_LIBS " -l${lib}")
  endforeach()
else()
  set(LOGRID_PC_DESCRIPTION "built without GL (the same as logrid-core)")
  set(LOGRID_PC_REQUIRES "logrid-core = ${PROJECT_VERSION}")
  set(LOGRID_PC_LIBS "")
endif()

configure_file(cmake/logrid-core.pc.in ${CMAKE_CURRENT_BINARY_DIR}/pkgconfig/logrid-core.pc @ONLY)
configure_file(cmake/logrid.pc.in ${CMAKE_CURRENT_BINARY_DIR}/pkgconfig/logrid.pc @ONLY)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/pkgconfig/logrid-core.pc
              ${CMAKE_CURRENT_BINARY_DIR}/pkgconfig/logrid.pc
        DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)

# ---------------------------------------------------------------------------
# Debian package: cpack -G DEB
# ---------------------------------------------------------------------------
set(LOGRID_PACKAGE_CONTACT "logrid developers" CACHE STRING
    "Maintainer field of the Debian package (name <email>)")

set(CPACK_PACKAGE_NAME logrid)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_CONTACT "${LOGRID_PACKAGE_CONTACT}")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
    "conservative image-space occlusion culling with a lazy occlusion grid (C++17)")
set(CPACK_PACKAGE_DESCRIPTION
    "logrid walks an application's bounding-box hierarchy front to back and culls every box\n\
hidden behind what is already drawn, reading the depth buffer lazily through a\n\
low-resolution grid of tiles. This package holds its static libraries (logrid::core,\n\
logrid::cpu, logrid::bvh and, when built with GL, logrid::zread and logrid::gl), their\n\
headers, the CMake package (find_package(logrid 0.1)) and the pkg-config modules\n\
logrid and logrid-core.")
# The package installs where the build was configured to install, so that the prefix in
# the pkg-config files is where the files are.
set(CPACK_PACKAGING_INSTALL_PREFIX "${CMAKE_INSTALL_PREFIX}")

set(CPACK_DEBIAN_PACKAGE_NAME liblogrid-dev)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)  # liblogrid-dev_<version>_<arch>.deb
set(CPACK_DEBIAN_PACKAGE_SECTION libdevel)
set(CPACK_DEBIAN_PACKAGE_PRIORITY optional)
# What a consumer of the static libraries needs on its machine. With GL: libepoxy to link
# (-lepoxy, epoxy.pc), pkg-config for logridConfig.cmake's find_dependency(PkgConfig);
# at run time EGL and GL with a driver (Mesa's llvmpipe runs without a GPU). GLM only for
# the optional header logrid/glm_camera.hpp.
if(LOGRID_BUILD_GL)
  set(CPACK_DEBIAN_PACKAGE_DEPENDS "libepoxy-dev, pkgconf | pkg-config")
  set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "libegl1, libgl1, libegl-mesa0, libgl1-mesa-dri")
endif()
set(CPACK_DEBIAN_PACKAGE_SUGGESTS "libglm-dev")

include(CPack)
