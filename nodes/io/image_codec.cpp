#include "nodes/io/image_codec.h"

#include <dlfcn.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <stdexcept>
#include <system_error>
#include <vector>

namespace orogen {

std::size_t pixel_type_size(PixelType t) {
  switch (t) {
    case PixelType::U8:
    case PixelType::I8:
      return 1;
    case PixelType::U16:
    case PixelType::I16:
    case PixelType::Half:
      return 2;
    case PixelType::U32:
    case PixelType::I32:
    case PixelType::F32:
      return 4;
    case PixelType::F64:
      return 8;
    case PixelType::Other:
      break;
  }
  return 0;
}

namespace {

namespace fs = std::filesystem;

// Where the module is looked for (see image_codec.h), in order.
std::vector<fs::path> candidate_paths() {
  if (const char* env = std::getenv("OROGEN_IMAGE_CODEC"); env && *env) return {fs::path(env)};
  std::vector<fs::path> paths;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) paths.push_back((exe.parent_path() / OROGEN_IMAGE_CODEC_INSTALL_RELPATH).lexically_normal());
  // The build tree's copy, only for programs of that build tree: an installed program never falls back to a
  // build directory that may be gone or of another version.
  const fs::path tree = fs::path(OROGEN_IMAGE_CODEC_BUILD_TREE).lexically_normal();
  const auto [end, _] = std::mismatch(tree.begin(), tree.end(), exe.begin(), exe.end());
  if (!ec && end == tree.end()) paths.push_back(OROGEN_IMAGE_CODEC_BUILD_PATH);
  return paths;
}

const ImageCodec* load_codec() {
  const std::vector<fs::path> paths = candidate_paths();
  std::string tried;
  for (std::size_t k = 0; k < paths.size(); ++k) {
    const fs::path& path = paths[k];
    std::error_code ec;
    // Without the override, a candidate that is not there is skipped (the next one may be); the last one, or
    // the override, is opened so the loader's reason is reported.
    if (paths.size() > 1 && k + 1 < paths.size() && !fs::exists(path, ec)) {
      tried += "'" + path.string() + "' (not found); ";
      continue;
    }
    // A path with a directory part, so dlopen never searches the library path for it.
    const fs::path open_path = path.has_parent_path() ? path : fs::path(".") / path;
    void* handle = dlopen(open_path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle) {
      const char* why = dlerror();
      tried += "'" + path.string() + "' (" + (why ? why : "unknown error") + "); ";
      continue;
    }
    using Entry = const ImageCodec* (*)();
    auto entry = reinterpret_cast<Entry>(dlsym(handle, OROGEN_IMAGE_CODEC_ENTRY));
    if (!entry) {
      tried += "'" + path.string() + "' (no " OROGEN_IMAGE_CODEC_ENTRY ": a module of another Orogen version); ";
      dlclose(handle);
      continue;
    }
    return entry();  // never unloaded: its writers and readers may live until exit
  }
  if (tried.size() >= 2) tried.resize(tried.size() - 2);
  const char* env = std::getenv("OROGEN_IMAGE_CODEC");
  throw std::runtime_error("cannot load the image codec module (which reads and writes PNG, EXR and TIFF files): " +
                           (env && *env ? "OROGEN_IMAGE_CODEC names " + tried
                                        : "tried " + (tried.empty() ? std::string("no path") : tried) +
                                              "; set OROGEN_IMAGE_CODEC to the path of orogen_image_codec.so"));
}

}  // namespace

const ImageCodec& image_codec() {
  static std::once_flag once;
  static const ImageCodec* codec = nullptr;
  static std::string failure;
  std::call_once(once, [] {
    try {
      codec = load_codec();
    } catch (const std::runtime_error& e) {
      failure = e.what();
    }
  });
  if (!codec) throw std::runtime_error(failure);
  return *codec;
}

}  // namespace orogen
