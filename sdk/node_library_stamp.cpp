// Compiled into every node library by orogen_add_node_library: the stamp the host reads from the file before
// opening it (graph/node_library.h). Tests override the version to build a library of "another" version.
#include "orogen/version.h"

#ifndef OROGEN_STAMP_VERSION
#define OROGEN_STAMP_VERSION OROGEN_SDK_VERSION
#endif
#ifndef OROGEN_STAMP_ABI
#define OROGEN_STAMP_ABI OROGEN_NODE_ABI
#endif
#define OROGEN_STAMP_TEXT(x) #x
#define OROGEN_STAMP_NUMBER(x) OROGEN_STAMP_TEXT(x)

extern "C" __attribute__((used, visibility("default"))) const char orogen_node_library_stamp[] =
    "orogen-node-library-stamp;name=" OROGEN_NODE_LIBRARY_NAME ";version=" OROGEN_STAMP_VERSION
    ";abi=" OROGEN_STAMP_NUMBER(OROGEN_STAMP_ABI) ";";
