#pragma once
// glTF files: the JSON document is serialized by tinygltf, the buffer is written by Orogen straight from its
// sources (the mesh's arrays, the instances) into the file, in one pass: no copy of the data into one vector,
// no base64 string of it in memory. Every byte goes through a CheckedFile, so a full disk fails the node
// (tinygltf's own file writer ignores short writes), and any failure inside tinygltf (std::bad_alloc on a huge
// scene, any exception) becomes a FileError naming the file. The bytes are those tinygltf writes for the same
// model with the buffer's data filled in.
#include <cstddef>
#include <filesystem>
#include <functional>
#include <vector>

namespace tinygltf {
class Model;
}

namespace orogen {

// The file's one buffer (buffer 0) as segments, each produced by its `emit` when the file is written.
class GltfBuffer {
 public:
  // Receives a segment's bytes in pieces of any size.
  using Sink = std::function<void(const void* data, std::size_t bytes)>;
  using Emit = std::function<void(const Sink& sink)>;

  // Appends a segment of `bytes` bytes at the next multiple of 4 (zero padding before it, as glTF's accessors
  // need aligned data); returns its offset. `emit` must pass exactly `bytes` bytes to its sink, and whatever it
  // reads must outlive the write.
  std::size_t add(std::size_t bytes, Emit emit);
  std::size_t size() const { return size_; }
  // The whole buffer, padding and segments in order; throws std::logic_error if a segment's size differs from
  // the one it was added with.
  void emit(const Sink& sink) const;

 private:
  struct Segment {
    std::size_t offset, bytes;
    Emit emit;
  };
  std::vector<Segment> segments_;
  std::size_t size_ = 0;
};

// Gathers values into 64 KiB pieces for a sink (call done() after the last).
template <class T>
class SinkStaging {
 public:
  explicit SinkStaging(const GltfBuffer::Sink& sink) : sink_(sink) {}
  void push(T value) {
    values_[n_++] = value;
    if (n_ == kCount) done();
  }
  void done() {
    if (n_) sink_(values_, n_ * sizeof(T));
    n_ = 0;
  }

 private:
  static constexpr std::size_t kCount = 65536 / sizeof(T);
  const GltfBuffer::Sink& sink_;
  T values_[kCount];
  std::size_t n_ = 0;
};

// Writes `model` (whose buffers are empty or one buffer without data, standing for `buffer`) as binary .glb
// (`binary`) or JSON .gltf with the buffer embedded as base64, to `path`, a new file (the temporary of an
// atomic write). Throws FileError. `progress` (a writer's cancellation check, which may throw) is called with
// the fraction of the file written after each MiB. (tinygltf's building of the JSON document is one call.)
void write_gltf_model(const tinygltf::Model& model, const GltfBuffer& buffer, const std::filesystem::path& path,
                      bool binary, const std::function<void(double)>& progress = {});

}  // namespace orogen
