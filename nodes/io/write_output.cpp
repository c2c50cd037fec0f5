#include "nodes/io/write_output.h"

#include <string>

#include "graph/atomic_file.h"

namespace orogen {

void write_node_output(ExecContext& ctx, std::string_view param,
                       const std::function<void(const std::filesystem::path&, const WriteProgress&)>& write) {
  const std::filesystem::path target = ctx.output_path(param);  // NodeError if the path rule refuses it
  const WriteProgress progress = [&ctx](double fraction) {
    ctx.check_cancelled();
    ctx.progress(fraction);
  };
  std::string temporary_name;
  try {
    prepare_output_directory(ctx.output_policy(), target);
    write_file_atomically(target, [&](const std::filesystem::path& temporary) {
      temporary_name = temporary.string();
      write(temporary, progress);
    });
  } catch (const Cancelled&) {
    throw;
  } catch (const NodeError&) {
    throw;
  } catch (const OutputPathError& e) {
    throw NodeError(e.what());
  } catch (const std::exception& e) {
    // FileError, filesystem_error (directory not creatable, rename failed), bad_alloc, ...
    // The user knows the file by its target name, not by the temporary one.
    std::string message = e.what();
    if (!temporary_name.empty())
      for (auto at = message.find(temporary_name); at != std::string::npos; at = message.find(temporary_name, at))
        message.replace(at, temporary_name.size(), target.string());
    if (message.find(target.string()) == std::string::npos) message = "cannot write '" + target.string() + "': " + message;
    throw NodeError(message);
  }
  ctx.record_written_file(target);
}

}  // namespace orogen
