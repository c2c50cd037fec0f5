#pragma once
// glTF files are serialized in memory by tinygltf and then written through a CheckedFile: every byte checked,
// so a full disk fails the node (tinygltf's own file writer ignores short writes), and any failure inside
// tinygltf (std::bad_alloc on a huge scene, any exception) becomes a FileError naming the file.
#include <filesystem>

namespace tinygltf {
class Model;
}

namespace orogen {

// Writes `model` as binary .glb (`binary`) or JSON .gltf (buffers embedded) to `path`, a new file (the
// temporary of an atomic write). Throws FileError.
void write_gltf_model(const tinygltf::Model& model, const std::filesystem::path& path, bool binary);

}  // namespace orogen
