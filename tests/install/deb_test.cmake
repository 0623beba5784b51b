# The deb_package test: build the .deb of `make package` from the (already built) build tree
# with CPack into WORK_DIR, unpack it with `dpkg -x` and run the packaged CLI's --version there,
# with no display.
#
#   cmake -DBUILD_DIR=… -DWORK_DIR=… -DCPACK=… -DDPKG=… -DDPKG_DEB=… -DVERSION=…
#         -P deb_test.cmake
include(${CMAKE_CURRENT_LIST_DIR}/common.cmake)
require(deb_test.cmake BUILD_DIR WORK_DIR CPACK DPKG DPKG_DEB VERSION)

file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})

run("cpack" ${CPACK} -G DEB --config ${BUILD_DIR}/CPackConfig.cmake -B ${WORK_DIR})
file(GLOB deb ${WORK_DIR}/motionmap_*.deb)
list(LENGTH deb count)
if(NOT count EQUAL 1)
  message(FATAL_ERROR "expected one motionmap_*.deb in ${WORK_DIR}, found: ${deb}")
endif()

# The control fields: the package's name and version, and the Qt and HDF5 runtime libraries
# among its dependencies (dpkg-shlibdeps found them in the binaries).
run("dpkg-deb -f" ${DPKG_DEB} -f ${deb} Package Version Depends)
message(STATUS "${deb}:\n${out}")
if(NOT out MATCHES "Package: motionmap\n")
  message(FATAL_ERROR "the package is not called motionmap")
endif()
if(NOT out MATCHES "Version: ${VERSION}\n")
  message(FATAL_ERROR "the package's version is not ${VERSION}")
endif()
foreach(lib libqt6gui6 libqt6widgets6 libqt6svg6 libqt6opengl6 libhdf5 libstdc\\+\\+6)
  if(NOT out MATCHES "Depends:.*${lib}")
    message(FATAL_ERROR "Depends does not name ${lib}")
  endif()
endforeach()

set(root ${WORK_DIR}/root)
run("dpkg -x" ${DPKG} -x ${deb} ${root})
foreach(file usr/bin/motionmap usr/bin/motionmap-studio
             usr/share/applications/motionmap-studio.desktop
             usr/share/icons/hicolor/scalable/apps/motionmap-studio.svg
             usr/include/motionmap/pipeline/clip_map.h)
  if(NOT EXISTS ${root}/${file})
    message(FATAL_ERROR "the package has no /${file}")
  endif()
endforeach()

# --version needs no display: DISPLAY and WAYLAND_DISPLAY are removed, no Qt platform is set.
run("motionmap --version" ${CMAKE_COMMAND} -E env --unset=DISPLAY --unset=WAYLAND_DISPLAY
    --unset=QT_QPA_PLATFORM ${root}/usr/bin/motionmap --version)
string(STRIP "${out}" out)
if(NOT out STREQUAL "motionmap ${VERSION}")
  message(FATAL_ERROR "/usr/bin/motionmap --version printed '${out}', expected 'motionmap ${VERSION}'")
endif()
message(STATUS "${root}/usr/bin/motionmap --version: ${out}")

# The Python module, when the build has it (MOTIONMAP_BUILD_PYTHON): in Debian's Python path, and
# importable from the unpacked package with Debian's interpreter. (No ';' in the Python code:
# CMake would split the argument there.)
file(GLOB python_module ${root}/usr/lib/python3/dist-packages/motionmap/_motionmap*.so)
if(python_module AND EXISTS /usr/bin/python3)
  foreach(file __init__.py _motionmap.pyi py.typed)
    if(NOT EXISTS ${root}/usr/lib/python3/dist-packages/motionmap/${file})
      message(FATAL_ERROR "the package has the Python extension but no motionmap/${file}")
    endif()
  endforeach()
  run("import motionmap" ${CMAKE_COMMAND} -E env PYTHONPATH=${root}/usr/lib/python3/dist-packages
      /usr/bin/python3 -c "import motionmap\nassert issubclass(motionmap.Error, ValueError)\nprint(motionmap.__file__)")
  string(STRIP "${out}" out)
  if(NOT out STREQUAL "${root}/usr/lib/python3/dist-packages/motionmap/__init__.py")
    message(FATAL_ERROR "import motionmap found '${out}', not the package's module")
  endif()
  message(STATUS "import motionmap: ${out}")
endif()
