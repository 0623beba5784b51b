# `cmake --install`: the stage libraries and their public headers, a MotionMapConfig.cmake for
# find_package(MotionMap), the CLI, and Studio with its .desktop file and icon (docs/install.md).
# Included last by the top-level CMakeLists.txt, once every target exists.
include(CMakePackageConfigHelpers)

set(MOTIONMAP_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/MotionMap
    CACHE STRING "Where MotionMapConfig.cmake is installed (relative to the prefix)")

# Every stage library (motionmap_stage() records their names) and the umbrella MotionMap::motionmap,
# in one export set: static libraries link each other, so they are exported together. A stage's
# headers go to include/motionmap/<stage>/, the path its include root gives them in the build
# tree; detail/ folders are private to the stage and stay out.
get_property(_mm_stages GLOBAL PROPERTY MOTIONMAP_STAGES)
foreach(_stage IN LISTS _mm_stages)
  install(TARGETS motionmap_${_stage} EXPORT MotionMapTargets
          ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/src/motionmap/${_stage}/
          DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/motionmap/${_stage}
          FILES_MATCHING PATTERN "*.h"
          PATTERN "detail" EXCLUDE)
endforeach()
install(TARGETS motionmap_all EXPORT MotionMapTargets)
install(EXPORT MotionMapTargets NAMESPACE MotionMap:: DESTINATION ${MOTIONMAP_INSTALL_CMAKEDIR})

# MotionMapConfig.cmake finds the public dependencies again (Eigen3, Threads, the HDF5 C library
# that mapfile links, and QtGui + QtSvg when render is installed: it links them). Spectra and
# nanoflann are header-only and private ($<BUILD_INTERFACE:…> in src/motionmap/CMakeLists.txt),
# so a consumer never needs them.
set(MOTIONMAP_INSTALLED_RENDER OFF)
if("render" IN_LIST _mm_stages)
  set(MOTIONMAP_INSTALLED_RENDER ON)
endif()
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/MotionMapConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/MotionMapConfig.cmake
                              INSTALL_DESTINATION ${MOTIONMAP_INSTALL_CMAKEDIR})
# 0.x: a minor release may change the API, so only the same major.minor is compatible.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/MotionMapConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/MotionMapConfig.cmake
              ${PROJECT_BINARY_DIR}/MotionMapConfigVersion.cmake
        DESTINATION ${MOTIONMAP_INSTALL_CMAKEDIR})

if(TARGET motionmap)
  install(TARGETS motionmap RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
endif()
if(TARGET motionmap-studio)
  install(TARGETS motionmap-studio RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  install(FILES ${PROJECT_SOURCE_DIR}/packaging/motionmap-studio.desktop
          DESTINATION ${CMAKE_INSTALL_DATADIR}/applications)
  install(FILES ${PROJECT_SOURCE_DIR}/packaging/motionmap-studio.svg
          DESTINATION ${CMAKE_INSTALL_DATADIR}/icons/hicolor/scalable/apps)
endif()

# `make package` (cpack -G DEB in the build directory): one package, motionmap, with all of the
# above under /usr. dpkg-shlibdeps (dpkg-dev) derives Depends from the binaries' shared libraries
# (libc6, libstdc++6, libqt6core6, libqt6gui6, libqt6svg6, libqt6widgets6, libqt6opengl6, …).
# Only for MotionMap's own build: a project that adds MotionMap with add_subdirectory() packages
# itself.
if(NOT _mm_top)
  return()
endif()
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME motionmap)
set(CPACK_PACKAGE_VENDOR "MotionMap")
# The Maintainer field; the repository names no contact, so set this when publishing a package.
set(MOTIONMAP_PACKAGE_MAINTAINER "MotionMap maintainers <maintainers@motionmap.invalid>"
    CACHE STRING "Maintainer field of the .deb built by `make package`")
set(CPACK_PACKAGE_CONTACT "${MOTIONMAP_PACKAGE_MAINTAINER}")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "map motion-capture clips to 2D trajectories")
# The long description, in lines of < 80 characters as Debian wants them.
string(CONCAT CPACK_PACKAGE_DESCRIPTION
  "MotionMap maps every frame of a motion-capture clip (BVH, Acclaim ASF/AMC) to\n"
  "a point on a 2D plane with PCA, SVD, MDS, Isomap, Laplacian eigenmaps or LLE,\n"
  "and synthesizes new poses and motions from the maps. This package holds the\n"
  "motionmap command-line tool, MotionMap Studio (a Qt 6 desktop application),\n"
  "the C++20 static libraries with their headers and CMake package files\n"
  "(find_package(MotionMap), which also needs libeigen3-dev and libhdf5-dev),\n"
  "and, when built with pybind11, the Python module motionmap (import motionmap).")
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)  # motionmap_<version>_<arch>.deb
set(CPACK_DEBIAN_PACKAGE_SECTION graphics)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
# The plots' labels; and what `import motionmap` needs when the Python module is in the package
# (its extension links no libpython, so dpkg-shlibdeps cannot see that).
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "fonts-dejavu-core")
if(TARGET motionmap_python)
  string(APPEND CPACK_DEBIAN_PACKAGE_RECOMMENDS ", python3, python3-numpy")
  set(CPACK_DEBIAN_PACKAGE_SUGGESTS "python3-sklearn, python3-h5py, python3-distributed, ")
endif()
string(APPEND CPACK_DEBIAN_PACKAGE_SUGGESTS "libeigen3-dev, libssl-dev, libhdf5-dev")  # find_package(MotionMap)
set(CPACK_STRIP_FILES ON)
include(CPack)
