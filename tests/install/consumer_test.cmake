# The install_consumer test: install the build tree into a fresh prefix, then configure, build
# and run tests/install/consumer against it, as a project outside MotionMap would.
#
#   cmake -DSOURCE_DIR=… -DBUILD_DIR=… -DWORK_DIR=… -DCONSUMER_DIR=… -DCONFIG=… -DGENERATOR=…
#         -DCXX_COMPILER=… [-DCXX_LAUNCHER=…] -DEXPECT=regex -P consumer_test.cmake
include(${CMAKE_CURRENT_LIST_DIR}/common.cmake)
require(consumer_test.cmake SOURCE_DIR BUILD_DIR WORK_DIR CONSUMER_DIR GENERATOR CXX_COMPILER EXPECT)

set(prefix ${WORK_DIR}/prefix)
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})

run("cmake --install" ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix} --config ${CONFIG})

# What was installed: the package files, public headers without detail/, and nothing that
# points back into the build or source tree or at the private header-only dependencies.
file(GLOB_RECURSE config LIST_DIRECTORIES false ${prefix}/*/MotionMapConfig.cmake)
if(NOT config)
  message(FATAL_ERROR "no MotionMapConfig.cmake under ${prefix}")
endif()
get_filename_component(config_dir ${config} DIRECTORY)
foreach(header core/error.h embed/embed.h pipeline/clip_map.h sample/sample_clip.h
               mapfile/map_file.h)
  if(NOT EXISTS ${prefix}/include/motionmap/${header})
    message(FATAL_ERROR "${prefix}/include/motionmap/${header} was not installed")
  endif()
endforeach()
file(GLOB_RECURSE private_headers ${prefix}/include/*/detail/*)
if(private_headers)
  message(FATAL_ERROR "detail/ headers were installed: ${private_headers}")
endif()
file(GLOB cmake_files ${config_dir}/*.cmake)
foreach(file IN LISTS cmake_files)
  file(READ ${file} text)
  foreach(bad Spectra nanoflann "${SOURCE_DIR}" "${BUILD_DIR}")
    string(FIND "${text}" "${bad}" at)
    if(at GREATER_EQUAL 0)
      message(FATAL_ERROR "${file} mentions ${bad}")
    endif()
  endforeach()
endforeach()

set(configure_args -S ${CONSUMER_DIR} -B ${WORK_DIR}/build -G ${GENERATOR}
                   -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_CXX_COMPILER=${CXX_COMPILER}
                   -DCMAKE_BUILD_TYPE=${CONFIG} -DCMAKE_FIND_PACKAGE_NO_PACKAGE_REGISTRY=ON)
if(CXX_LAUNCHER)
  list(APPEND configure_args -DCMAKE_CXX_COMPILER_LAUNCHER=${CXX_LAUNCHER})
endif()
run("configuring the consumer" ${CMAKE_COMMAND} ${configure_args})
run("building the consumer" ${CMAKE_COMMAND} --build ${WORK_DIR}/build --config ${CONFIG})

file(GLOB_RECURSE exe LIST_DIRECTORIES false ${WORK_DIR}/build/consumer ${WORK_DIR}/build/*/consumer)
if(NOT exe)
  message(FATAL_ERROR "the consumer was built, but no ${WORK_DIR}/build/consumer")
endif()
list(GET exe 0 exe)
run("running the consumer" ${exe})
message(STATUS "${out}")
if(NOT out MATCHES "${EXPECT}")
  message(FATAL_ERROR "the consumer printed\n${out}\nexpected a match of ${EXPECT}")
endif()
message(STATUS "consumer built against ${prefix} and ran")
