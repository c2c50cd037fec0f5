// PNG and EXR read by libpng and OpenEXR directly (nodes/io/native) must give what the image codec
// (OpenImageIO) gives for the same file: the header, every channel's native samples bit for bit, and the
// attributes heights need. Files they do not read are left to the codec (nullptr), never misread.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include <Imath/half.h>
#include <OpenImageIO/imageio.h>

#include "nodes/io/image_codec.h"
#include "nodes/io/native/native_image_readers.h"
#include "support/run_process.h"
#include "support/test_paths.h"

namespace orogen::test {
namespace {

namespace fs = std::filesystem;

// A file of `channels` channels of `type`, random samples, with the attributes Orogen's height writer sets.
fs::path write_image(const fs::path& path, int width, int height, int channels, OIIO::TypeDesc type,
                     const std::vector<std::pair<std::string, std::string>>& attributes = {}, int x = 0, int y = 0,
                     int tile = 0) {
  OIIO::ImageSpec spec(width, height, channels, type);
  spec.x = x;
  spec.y = y;
  if (tile) spec.tile_width = spec.tile_height = tile;
  for (const auto& [name, value] : attributes) spec.attribute(name, value);
  std::vector<unsigned char> px(spec.image_bytes());
  std::mt19937 rng(static_cast<unsigned>(width * 31 + channels));
  for (auto& b : px) b = static_cast<unsigned char>(rng());
  if (type == OIIO::TypeDesc::HALF || type == OIIO::TypeDesc::FLOAT)  // finite values, signs and zeros included
    for (std::size_t k = 0; k < px.size() / type.size(); ++k) {
      const float v = static_cast<float>(static_cast<int>(rng() % 20001) - 10000) / 7.0f;
      if (type == OIIO::TypeDesc::FLOAT) {
        std::memcpy(px.data() + 4 * k, &v, 4);
      } else {
        const Imath::half h(v);
        const std::uint16_t bits = h.bits();
        std::memcpy(px.data() + 2 * k, &bits, 2);
      }
    }
  auto out = OIIO::ImageOutput::create(path.string());
  EXPECT_TRUE(out && out->open(path.string(), spec)) << path;
  EXPECT_TRUE(out->write_image(type, px.data()));
  out->close();
  return path;
}

// The native reader of `path` against the codec's: header, samples (whole image and bands), attributes.
void expect_as_the_codec_reads(const fs::path& path) {
  SCOPED_TRACE(path.filename().string());
  const std::string extension = path.extension().string().substr(1);
  auto native = open_native_image_reader(extension, path.string());
  ASSERT_TRUE(native) << "the native reader refused the file";
  auto codec = image_codec().create_reader(extension);
  ASSERT_TRUE(codec && codec->open(path.string())) << codec->error();
  const ImageInfo &a = native->info(), &b = codec->info();
  EXPECT_EQ(a.x, b.x);
  EXPECT_EQ(a.y, b.y);
  ASSERT_EQ(a.width, b.width);
  ASSERT_EQ(a.height, b.height);
  ASSERT_EQ(a.channels, b.channels);
  EXPECT_EQ(a.format, b.format);
  EXPECT_EQ(a.channel_types, b.channel_types);
  EXPECT_EQ(a.channel_type_texts, b.channel_type_texts);
  EXPECT_EQ(a.channel_sizes, b.channel_sizes);
  for (const char* name : {"orogen:height_min", "orogen:height_max", "ImageDescription", "Software"})
    EXPECT_EQ(native->string_attribute(name), codec->string_attribute(name)) << name;
  const std::size_t size = a.channel_sizes[0];
  for (int c = 0; c < a.channels; ++c) {
    std::vector<unsigned char> mine(static_cast<std::size_t>(a.width) * a.height * size), theirs(mine.size());
    ASSERT_TRUE(native->read_image(c, c + 1, a.format, mine.data())) << native->error();
    ASSERT_TRUE(codec->read_image(c, c + 1, b.format, theirs.data())) << codec->error();
    ASSERT_EQ(mine, theirs) << "channel " << c;
  }
  // Bands of rows in order, then an earlier band again (a reader that streams must start over). The codec reads
  // a tiled file by tiles only: the whole image above is the comparison there.
  if (b.tile_width > 0) return;
  const std::size_t row = static_cast<std::size_t>(a.width) * a.channels * size;
  std::vector<unsigned char> mine(row * 5), theirs(row * 5);
  for (const int first : {0, 5, 10, 3}) {
    if (first + 5 > a.height) continue;
    ASSERT_TRUE(native->read_native_scanlines(a.y + first, a.y + first + 5, 0, a.channels, mine.data()))
        << native->error();
    ASSERT_TRUE(codec->read_native_scanlines(b.y + first, b.y + first + 5, 0, b.channels, theirs.data()));
    ASSERT_EQ(mine, theirs) << "rows from " << first;
  }
}

const std::vector<std::pair<std::string, std::string>> kHeightAttributes = {
    {"orogen:height_min", "-12.5"}, {"orogen:height_max", "1040.25"}, {"ImageDescription", "Orogen heightfield"}};

TEST(NativeReaders, PngReadsAsTheCodecDoes) {
  const fs::path dir = scratch_dir("native-png");
  for (const int channels : {1, 2, 3, 4})
    for (const OIIO::TypeDesc type : {OIIO::TypeDesc::UINT8, OIIO::TypeDesc::UINT16})
      expect_as_the_codec_reads(
          write_image(dir / ("c" + std::to_string(channels) + "_" + std::to_string(type.size() * 8) + ".png"), 37, 23,
                      channels, type, kHeightAttributes));
}

TEST(NativeReaders, ExrReadsAsTheCodecDoes) {
  const fs::path dir = scratch_dir("native-exr");
  for (const OIIO::TypeDesc type : {OIIO::TypeDesc::HALF, OIIO::TypeDesc::FLOAT, OIIO::TypeDesc::UINT32})
    expect_as_the_codec_reads(
        write_image(dir / ("t" + std::to_string(type.size()) + ".exr"), 41, 29, 1, type, kHeightAttributes));
  // A data window away from the origin, and a tiled file.
  expect_as_the_codec_reads(write_image(dir / "window.exr", 19, 17, 1, OIIO::TypeDesc::FLOAT, {}, -4, 7));
  expect_as_the_codec_reads(write_image(dir / "tiled.exr", 50, 45, 1, OIIO::TypeDesc::FLOAT, {}, 0, 0, 16));
  // Uncompressed, as Orogen writes heights: rows copied from the file's chunks.
  for (const OIIO::TypeDesc type : {OIIO::TypeDesc::HALF, OIIO::TypeDesc::FLOAT, OIIO::TypeDesc::UINT32})
    expect_as_the_codec_reads(write_image(dir / ("raw" + std::to_string(type.size()) + ".exr"), 43, 31, 1, type,
                                          {{"compression", "none"}}, -3, 5));
}

// What the native readers leave to the codec: it presents these differently (expanded palettes, an alpha made
// of tRNS, reordered channels) or they are not images at all.
TEST(NativeReaders, OtherFilesAreLeftToTheCodec) {
  const fs::path dir = scratch_dir("native-refused");
  EXPECT_FALSE(open_native_exr(write_image(dir / "rgb.exr", 8, 8, 3, OIIO::TypeDesc::FLOAT).string()));
  write_text(dir / "damaged.png", "\x89PNG\r\n\x1a\n not really");
  write_text(dir / "damaged.exr", "v/1\x01 not really");
  EXPECT_FALSE(open_native_png((dir / "damaged.png").string()));
  EXPECT_FALSE(open_native_exr((dir / "damaged.exr").string()));
  EXPECT_FALSE(open_native_png((dir / "missing.png").string()));
  EXPECT_FALSE(open_native_image_reader("tif", (dir / "damaged.png").string()));
  // An interlaced PNG.
  {
    OIIO::ImageSpec spec(9, 9, 1, OIIO::TypeDesc::UINT8);
    spec.attribute("png:interlace", 1);
    std::vector<unsigned char> px(81, 7);
    auto out = OIIO::ImageOutput::create((dir / "interlaced.png").string());
    ASSERT_TRUE(out && out->open((dir / "interlaced.png").string(), spec));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, px.data()));
    out->close();
  }
  // OpenImageIO may not write interlaced PNGs: the reader must then read it (and match the codec).
  auto interlaced = open_native_png((dir / "interlaced.png").string());
  if (interlaced) expect_as_the_codec_reads(dir / "interlaced.png");
}

}  // namespace
}  // namespace orogen::test
