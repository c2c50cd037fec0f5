// libFuzzer target: the graph-file reader (JSON parsing, migration, validation of every node and parameter).
// Seed corpus: graphs/*.json, the subgraph library graphs/library/*.json and tests/fuzz/graph_file_seeds
// (interface sections, Subgraph instances and their errors, embedded assets "#name"); dictionary:
// tests/fuzz/graph_file.dict. Assets named by a path resolve against the current directory (fuzz.sh runs in the
// repository).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "graph/graph_file.h"
#include "graph/subgraph.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  auto loaded = orogen::parse_graph(text);
  if (loaded.ok()) {
    // A graph that loads must also serialise (the editor saves what it loaded).
    (void)orogen::serialize_graph(*loaded.graph);
    // Instances expand into plain nodes before evaluation; an exposed value that an inner parameter refuses is
    // a GraphError naming the instance, anything else a bug.
    if (orogen::has_subgraphs(*loaded.graph)) {
      try {
        (void)orogen::expand_subgraphs(*loaded.graph);
      } catch (const orogen::GraphError&) {}
    }
  } else {
    (void)loaded.error_text();
  }
  return 0;
}
