// libFuzzer target: the graph-file reader (JSON parsing, migration, validation of every node and parameter).
// Seed corpus: graphs/*.json; dictionary: tests/fuzz/graph_file.dict.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "graph/graph_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  auto loaded = orogen::parse_graph(text);
  if (loaded.ok()) {
    // A graph that loads must also serialise (the editor saves what it loaded).
    (void)orogen::serialize_graph(*loaded.graph);
  } else {
    (void)loaded.error_text();
  }
  return 0;
}
