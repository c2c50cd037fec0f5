#pragma once
// glTF files are serialized by tinygltf into a CheckedOStream: every byte checked, so a full disk fails the
// node (tinygltf's own file writer ignores short writes), and any failure inside tinygltf (std::bad_alloc on
// a huge scene, any exception) becomes a FileError naming the file.
#include <filesystem>
#include <functional>

namespace tinygltf {
class Model;
}

namespace orogen {

// Writes `model` as binary .glb (`binary`) or JSON .gltf (buffers embedded) to `path`, a new file (the
// temporary of an atomic write). Throws FileError. `poll` (a writer's cancellation check) runs after each
// 64 KiB written; what it throws is rethrown. (tinygltf's building of its JSON document, and the base64 text of
// the buffer in .gltf, are single calls that cannot be polled.)
void write_gltf_model(const tinygltf::Model& model, const std::filesystem::path& path, bool binary,
                      const std::function<void()>& poll = {});

}  // namespace orogen
