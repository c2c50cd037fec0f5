// libFuzzer target: heightfield images a user feeds to ReadHeightfield (PNG, EXR, TIFF, RAW16), through the
// node itself. The first input byte picks the format (the file's extension); the rest is the file.
// Seed corpus: tests/fuzz/make_image_seeds.sh writes small valid files of each format.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>

#include <OpenImageIO/imageio.h>

#include "evaluator/run_node.h"
#include "graph/domain.h"

namespace {

const char* const kExtensions[] = {".png", ".exr", ".tif", ".r16"};

std::filesystem::path scratch_file(const char* ext) {
  static const std::filesystem::path dir = [] {
    auto d = std::filesystem::temp_directory_path() / ("orogen-fuzz-image-" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    return d;
  }();
  return dir / (std::string("input") + ext);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const char* ext = kExtensions[data[0] % 4];
  const auto path = scratch_file(ext);
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data + 1), static_cast<std::streamsize>(size - 1));
  }
  // Headers claiming huge images are refused by the reader (65536 per side), but even that much would exceed
  // the fuzzer's memory limit: skip those the header says are above 4 M pixels.
  if (std::string(ext) != ".r16") {
    // The extension's reader only, as ReadHeightfield does.
    if (auto in = OIIO::ImageInput::create(std::string(ext + 1), /*do_open=*/false)) {
      OIIO::ImageSpec spec;
      if (in->open(path.string(), spec) && static_cast<double>(spec.width) * spec.height * spec.nchannels > 4e6)
        return 0;
    }
  }
  try {
    const orogen::Domain domain = orogen::Domain::from_extent({0, 0}, {100, 100}, {17, 9});
    (void)orogen::run_node("ReadHeightfield", domain, {{"path", path.string()}}, {});
  } catch (const std::exception&) {
    // FileError, NodeError: a clear refusal is the expected outcome for a damaged file.
  }
  return 0;
}
