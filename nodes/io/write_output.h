#pragma once
// The common part of every writer node: resolve the output path under the output policy, write atomically
// (temporary file beside the target, then rename), record the written file, and turn failures into a
// NodeError naming the file. Cancellation passes through untouched.
#include <filesystem>
#include <functional>
#include <string_view>

#include "graph/exec_context.h"
#include "nodes/io/file_error.h"

namespace orogen {

// Calls write(temporary, progress) to produce the file designated by output-path parameter `param`.
// `progress` reports to the node's progress and throws Cancelled when the run is cancelled.
void write_node_output(ExecContext& ctx, std::string_view param,
                       const std::function<void(const std::filesystem::path& temporary, const WriteProgress& progress)>& write);

}  // namespace orogen
