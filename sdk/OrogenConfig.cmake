# find_package(Orogen): the installed node SDK (docs/plugins.md).
#
#   Orogen::headers            the public headers, for node libraries
#   Orogen::testing            the headers and libraries a test program of nodes links (<orogen/testing.h>)
#   orogen_add_node_library()  builds a node library Orogen loads with --plugin (OrogenNodeLibrary.cmake)
#   OROGEN_EXECUTABLE          the installed `orogen` program (to load and test a library: orogen test-node)
include(CMakeFindDependencyMacro)
find_dependency(glm CONFIG)

get_filename_component(_orogen_prefix "${CMAKE_CURRENT_LIST_DIR}/../../.." ABSOLUTE)
if(NOT TARGET Orogen::headers)
  add_library(Orogen::headers INTERFACE IMPORTED)
  set_target_properties(Orogen::headers PROPERTIES
    INTERFACE_INCLUDE_DIRECTORIES "${_orogen_prefix}/include/orogen"
    INTERFACE_LINK_LIBRARIES glm::glm
    INTERFACE_COMPILE_FEATURES cxx_std_20)
endif()

# The testing kit links the SDK's static libraries into the test program, with their own dependencies.
if(NOT TARGET Orogen::testing)
  find_dependency(TBB CONFIG)
  find_dependency(nlohmann_json CONFIG)
  find_dependency(OpenMesh CONFIG)
  find_dependency(GTest)
  find_dependency(PkgConfig)
  pkg_check_modules(OROGEN_XXHASH REQUIRED IMPORTED_TARGET libxxhash)
  pkg_check_modules(OROGEN_ZSTD REQUIRED IMPORTED_TARGET libzstd)
  add_library(Orogen::testing INTERFACE IMPORTED)
  set(_orogen_lib "${_orogen_prefix}/lib")
  set_target_properties(Orogen::testing PROPERTIES
    INTERFACE_LINK_LIBRARIES "Orogen::headers;${_orogen_lib}/liborogen_testing.a;${_orogen_lib}/liborogen_evaluator.a;\
${_orogen_lib}/liborogen_graph.a;TBB::tbb;nlohmann_json::nlohmann_json;OpenMeshCore;PkgConfig::OROGEN_XXHASH;\
PkgConfig::OROGEN_ZSTD;GTest::gtest;${CMAKE_DL_LIBS}")
endif()

set(OROGEN_EXECUTABLE "${_orogen_prefix}/bin/orogen")
set(OROGEN_NODE_LIBRARY_STAMP_SOURCE "${CMAKE_CURRENT_LIST_DIR}/node_library_stamp.cpp")
include("${CMAKE_CURRENT_LIST_DIR}/OrogenNodeLibrary.cmake")
