#include "nodes/io/write_output.h"

#include <new>
#include <string>

#include "graph/atomic_file.h"

namespace orogen {
namespace {

// The user knows a file by its target name, not by the temporary one.
std::string with_target_names(std::string message, const std::vector<std::string>& temporaries,
                              const std::vector<NodeOutputFile>& files) {
  for (std::size_t k = 0; k < temporaries.size() && k < files.size(); ++k) {
    const std::string& temporary = temporaries[k];
    const std::string target = files[k].target.string();
    if (temporary.empty()) continue;
    for (auto at = message.find(temporary); at != std::string::npos; at = message.find(temporary, at + target.size()))
      message.replace(at, temporary.size(), target);
  }
  return message;
}

}  // namespace

void write_node_files(ExecContext& ctx, const std::vector<NodeOutputFile>& files) {
  const WriteProgress progress = [&ctx](double fraction) {
    ctx.check_cancelled();
    ctx.progress(fraction);
  };
  std::vector<std::string> temporaries(files.size());
  std::string failing = files.empty() ? std::string() : files.back().target.string();
  try {
    // Every file is checked before any is written: a side file never goes where its main file may not. The
    // main file comes last (files are renamed after what they name), and is checked first to be the one named.
    for (auto f = files.rbegin(); f != files.rend(); ++f) {
      failing = f->target.string();
      prepare_output_directory(ctx.output_policy(), f->target);
    }
    std::vector<AtomicWrite> writes;
    for (std::size_t k = 0; k < files.size(); ++k)
      writes.push_back({files[k].target, [&, k](const std::filesystem::path& temporary) {
                          failing = files[k].target.string();
                          temporaries[k] = temporary.string();
                          files[k].write(temporary, progress);
                        }});
    write_files_atomically(writes);
  } catch (const Cancelled&) {
    throw;
  } catch (const NodeError&) {
    throw;
  } catch (const OutputPathError& e) {
    throw NodeError(e.what());
  } catch (const std::bad_alloc&) {
    throw NodeError("cannot write '" + failing + "': out of memory while encoding the file");
  } catch (const std::exception& e) {
    // FileError, WriteError, filesystem_error (directory not creatable, rename failed), a library's own ...
    std::string message = with_target_names(e.what(), temporaries, files);
    if (message.find(failing) == std::string::npos) message = "cannot write '" + failing + "': " + message;
    throw NodeError(message);
  } catch (...) {
    throw NodeError("cannot write '" + failing + "': the file writer failed with an unknown exception");
  }
  for (const auto& f : files) ctx.record_written_file(f.target);
}

void write_node_output(ExecContext& ctx, std::string_view param, const NodeFileWriter& write) {
  write_node_files(ctx, {{ctx.output_path(param), write}});  // NodeError if the path rule refuses it
}

}  // namespace orogen
