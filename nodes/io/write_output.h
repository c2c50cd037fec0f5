#pragma once
// The common part of every writer node: resolve the output paths under the output policy and check every one
// on the real file system (no link out of the output directory) before anything is written, write them
// atomically (temporaries beside the targets, renamed only once all are written), record the written files,
// and turn any failure of the writer, a third-party library's included (std::bad_alloc, any exception), into
// a NodeError naming the file. Cancellation passes through untouched.
#include <filesystem>
#include <functional>
#include <string_view>
#include <vector>

#include "graph/exec_context.h"
#include "nodes/io/file_error.h"

namespace orogen {

using NodeFileWriter = std::function<void(const std::filesystem::path& temporary, const WriteProgress& progress)>;

// One file a node writes: the main output (from ctx.output_path) or a side file derived from it (a material
// library beside an OBJ).
struct NodeOutputFile {
  std::filesystem::path target;
  NodeFileWriter write;
};

// Writes `files`, renamed in the given order (a file that names another comes after it). `progress` reports
// to the node's progress and throws Cancelled when the run is cancelled.
void write_node_files(ExecContext& ctx, const std::vector<NodeOutputFile>& files);

// Calls write(temporary, progress) to produce the file designated by output-path parameter `param`.
void write_node_output(ExecContext& ctx, std::string_view param, const NodeFileWriter& write);

}  // namespace orogen
