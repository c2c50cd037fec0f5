#pragma once
// Image writers (nodes/io/image_codec.h) through a CheckedFile: every byte the format plugin writes is
// checked, so a full disk fails the write (OpenImageIO's own file proxy ignores short writes of the PNG plugin
// and close errors), and the file is synced before it is renamed over the previous one.
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>

#include "graph/checked_file.h"
#include "nodes/io/file_error.h"
#include "nodes/io/file_extension.h"
#include "nodes/io/image_codec.h"
#include "nodes/io/native/native_image_writers.h"

namespace orogen {

class CheckedImageSink final : public ImageByteSink {
 public:
  explicit CheckedImageSink(const std::filesystem::path& path) : file_(path) {}
  bool pwrite(const void* data, std::size_t size, std::int64_t offset) override {
    return file_.pwrite(data, size, offset);
  }
  std::int64_t size() const override { return file_.size(); }
  CheckedFile& file() { return file_; }

 private:
  CheckedFile file_;
};

// The image codec, or a FileError about `path` saying why it cannot be loaded.
inline const ImageCodec& image_codec_for(const std::filesystem::path& path, const char* verb) {
  try {
    return image_codec();
  } catch (const std::runtime_error& e) {
    throw FileError(std::string("cannot ") + verb + " '" + path.string() + "': " + e.what());
  }
}

// A writer for the format of `format_name`'s extension, writing `spec` into `sink`; null with `error` set when
// the format is unknown or cannot be opened. Files the native writers write exactly as the codec would
// (nodes/io/native/native_image_writers.h) never load the codec; throws FileError when it is needed and cannot
// be loaded.
inline std::unique_ptr<ImageWriter> create_checked_output(const std::filesystem::path& format_name,
                                                          CheckedImageSink& sink, const ImageWriteSpec& spec,
                                                          std::string& error) {
  const std::string ext = lower_extension(format_name);
  auto out = create_native_image_writer(ext.empty() ? ext : ext.substr(1), sink, spec, error);
  if (!out && error.empty())
    out = image_codec_for(format_name, "write").create_writer(format_name.string(), sink, spec, error);
  // A plugin that writes its header on open reports "could not open" for a full disk: give the reason.
  if (!out && !sink.file().ok()) error = sink.file().error();
  return out;
}

}  // namespace orogen
