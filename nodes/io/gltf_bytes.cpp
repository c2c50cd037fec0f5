#include "nodes/io/gltf_bytes.h"

#include <new>
#include <sstream>
#include <string>

#include <tiny_gltf.h>

#include "graph/checked_file.h"
#include "nodes/io/file_error.h"

namespace orogen {

void write_gltf_model(const tinygltf::Model& model, const std::filesystem::path& path, bool binary) {
  std::string bytes;
  try {
    std::ostringstream stream;
    tinygltf::TinyGLTF writer;
    if (!writer.WriteGltfSceneToStream(&model, stream, !binary, binary) || !stream)
      throw FileError("cannot write '" + path.string() + "': glTF serialization failed");
    bytes = std::move(stream).str();
  } catch (const FileError&) {
    throw;
  } catch (const std::bad_alloc&) {
    throw FileError("cannot write '" + path.string() + "': out of memory while serializing the glTF file");
  } catch (const std::exception& e) {
    throw FileError("cannot write '" + path.string() + "': glTF serialization failed: " + e.what());
  }
  try {
    CheckedFile out(path);
    out.write(bytes.data(), bytes.size());
    out.finish();
  } catch (const WriteError& e) {
    throw FileError(e.what());
  }
}

}  // namespace orogen
