#pragma once
// OpenImageIO writers through a CheckedFile: every byte the format plugin writes is checked, so a full disk
// fails the write (OpenImageIO's own file proxy ignores short writes of the PNG plugin and close errors),
// and the file is synced before it is renamed over the previous one.
#include <filesystem>
#include <memory>

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include "graph/checked_file.h"

namespace orogen {

class CheckedIOProxy final : public OIIO::Filesystem::IOProxy {
 public:
  explicit CheckedIOProxy(const std::filesystem::path& path) : IOProxy(path.string(), Write), file_(path) {}
  const char* proxytype() const override { return "orogen-checked"; }
  void close() override {}
  bool seek(int64_t offset) override {
    if (offset < 0) return false;
    m_pos = offset;
    return true;
  }
  size_t write(const void* buf, size_t size) override {
    if (!file_.pwrite(buf, size, m_pos)) return 0;
    m_pos += static_cast<int64_t>(size);
    return size;
  }
  size_t pwrite(const void* buf, size_t size, int64_t offset) override {
    return file_.pwrite(buf, size, offset) ? size : 0;
  }
  size_t read(void*, size_t) override { return 0; }
  size_t pread(void*, size_t, int64_t) override { return 0; }
  size_t size() const override { return static_cast<size_t>(file_.size()); }
  CheckedFile& file() { return file_; }

 private:
  CheckedFile file_;
};

// An ImageOutput for the format of `format_name`'s extension, opened on `proxy` with `spec`; throws
// FileError (via the callback `fail`) when the format is unknown or cannot be opened.
inline std::unique_ptr<OIIO::ImageOutput> create_checked_output(const std::filesystem::path& format_name,
                                                                CheckedIOProxy& proxy, const OIIO::ImageSpec& spec,
                                                                std::string& error) {
  auto out = OIIO::ImageOutput::create(format_name.string());
  if (!out) {
    error = OIIO::geterror();
    return nullptr;
  }
  if (!out->supports("ioproxy")) {
    error = std::string("the ") + out->format_name() + " writer cannot write through a checked file";
    return nullptr;
  }
  out->set_ioproxy(&proxy);
  if (!out->open(proxy.filename(), spec)) {
    // A plugin that writes its header on open reports "could not open" for a full disk: give the reason.
    error = proxy.file().ok() ? out->geterror() : proxy.file().error();
    return nullptr;
  }
  return out;
}

}  // namespace orogen
