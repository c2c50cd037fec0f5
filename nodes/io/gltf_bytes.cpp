#include "nodes/io/gltf_bytes.h"

#include <memory>
#include <new>
#include <string>

#include <tiny_gltf.h>

#include "graph/checked_file.h"
#include "nodes/io/file_error.h"

namespace orogen {

void write_gltf_model(const tinygltf::Model& model, const std::filesystem::path& path, bool binary,
                      const std::function<void()>& poll) {
  std::unique_ptr<CheckedOStream> stream;
  try {
    stream = std::make_unique<CheckedOStream>(path);
  } catch (const WriteError& e) {
    throw FileError(e.what());
  }
  // tinygltf writes the JSON and the buffer through the stream; the poll runs after each 64 KiB, and what it
  // throws (Cancelled) stops the stream and is rethrown here.
  if (poll) stream->set_poll(poll);
  bool written = false;
  try {
    tinygltf::TinyGLTF writer;
    written = writer.WriteGltfSceneToStream(&model, *stream, !binary, binary);
  } catch (const std::bad_alloc&) {
    throw FileError("cannot write '" + path.string() + "': out of memory while serializing the glTF file");
  } catch (const std::exception& e) {
    throw FileError("cannot write '" + path.string() + "': glTF serialization failed: " + e.what());
  }
  stream->rethrow_poll();
  if (!stream->file().ok()) throw FileError(stream->file().error());
  if (!written || stream->bad()) throw FileError("cannot write '" + path.string() + "': glTF serialization failed");
  try {
    stream->finish();
  } catch (const WriteError& e) {
    throw FileError(e.what());
  }
}

}  // namespace orogen
