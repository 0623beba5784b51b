# Helpers for MotionMap's targets: one library per pipeline stage, whose headers only the stages
# that link it can include, and one set of warning flags for every target of the project.

# Warnings are errors in MotionMap's own builds (CI included); a project that adds MotionMap with
# add_subdirectory() gets the warnings but not -Werror.
if(NOT DEFINED _mm_top)
  set(_mm_top OFF)
endif()
option(MOTIONMAP_WERROR "Treat compiler warnings as errors" ${_mm_top})

# motionmap_warnings(target): the project's warning flags (library, apps, tests, benchmarks and
# fuzzers alike).
function(motionmap_warnings target)
  # -Wno-restrict: g++ 12 reports false positives on std::string concatenation (GCC bug 105329).
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic
                         $<$<CXX_COMPILER_ID:GNU>:-Wno-restrict>
                         $<$<BOOL:${MOTIONMAP_WERROR}>:-Werror>)
endfunction()

# motionmap_stage(name DEPENDS stage… [SOURCES file…]): the static library motionmap_<name>
# (alias MotionMap::<name>) from src/motionmap/<name>/*.cpp, or the SOURCES given.
#
# How the layering is enforced: a stage's headers are reachable only through its own include
# root, ${CMAKE_BINARY_DIR}/layers/<name>, which holds nothing but the link
# motionmap/<name> → src/motionmap/<name>. The root is a PUBLIC include directory of the stage,
# so it reaches exactly the targets that link the stage (directly or through a later one). A
# source that includes "motionmap/<other>/x.h" of a stage it does not link fails to compile
# with "No such file or directory"; a call into it would fail to link.
function(motionmap_stage name)
  cmake_parse_arguments(ARG "" "" "DEPENDS;SOURCES" ${ARGN})
  set(dir ${PROJECT_SOURCE_DIR}/src/motionmap/${name})
  if(NOT ARG_SOURCES)
    file(GLOB ARG_SOURCES CONFIGURE_DEPENDS ${dir}/*.cpp)
  endif()
  set(root ${CMAKE_BINARY_DIR}/layers/${name})
  file(MAKE_DIRECTORY ${root}/motionmap)
  file(CREATE_LINK ${dir} ${root}/motionmap/${name} SYMBOLIC)

  set(target motionmap_${name})
  add_library(${target} STATIC ${ARG_SOURCES})
  add_library(MotionMap::${name} ALIAS ${target})
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${name} POSITION_INDEPENDENT_CODE ON)
  target_include_directories(${target} PUBLIC $<BUILD_INTERFACE:${root}>
                                              $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_compile_features(${target} PUBLIC cxx_std_20)
  foreach(dep IN LISTS ARG_DEPENDS)
    target_link_libraries(${target} PUBLIC motionmap_${dep})
  endforeach()
  motionmap_warnings(${target})
  set_property(GLOBAL APPEND PROPERTY MOTIONMAP_STAGES ${name})
endfunction()
