# orogen_add_node_library(NAME SOURCES...): a node library Orogen loads at run time (docs/plugins.md).
#
# A MODULE library: it links no copy of Orogen. Its references to the SDK resolve, when it is opened, against
# the host program (orogen, orogen-editor), which exports its symbols, so a node registers into the host's one
# registry. The stamp compiled into it names the library, the SDK version and the node ABI.
# Needs the target Orogen::headers and OROGEN_NODE_LIBRARY_STAMP_SOURCE (set by OrogenConfig.cmake, or by the
# Orogen build itself).
function(orogen_add_node_library name)
  if(NOT ARGN)
    message(FATAL_ERROR "orogen_add_node_library(${name}): no sources")
  endif()
  add_library(${name} MODULE ${ARGN} ${OROGEN_NODE_LIBRARY_STAMP_SOURCE})
  target_link_libraries(${name} PRIVATE Orogen::headers)
  target_compile_features(${name} PRIVATE cxx_std_20)
  target_compile_definitions(${name} PRIVATE OROGEN_NODE_LIBRARY_NAME="${name}")
  # Only the stamp needs to be seen from outside; the node code registers itself from its initialisers.
  set_target_properties(${name} PROPERTIES CXX_VISIBILITY_PRESET hidden VISIBILITY_INLINES_HIDDEN ON)
endfunction()
