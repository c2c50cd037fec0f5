#pragma once
// Helpers for the editor's headless tests: a scratch directory and a small graph of the test node types
// registered in editor_test_nodes.cpp (EdSource -> EdBlend -> EdBlend, EdScatter for a Points output).
#include <filesystem>
#include <string>

#include "graph/graph.h"

namespace orogen::editor::test {

// A new empty directory, unique per call.
std::filesystem::path scratch_dir(const std::string& name);

// src (EdSource) -> mid (EdBlend.a) -> out (EdBlend.a), plus scatter (EdScatter) reading src; positions set.
Graph chain_graph();

}  // namespace orogen::editor::test
