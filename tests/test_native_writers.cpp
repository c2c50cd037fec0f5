// EXR and PNG written by OpenEXR and libpng directly (nodes/io/native) must be the file the image codec
// (OpenImageIO) writes for the same spec and samples, byte for byte: the specs Orogen's height, image and mosaic
// writers make, every codec, zlib level and row filter they use, one to five channels, 8- and 16-bit, half, float and
// uint samples, rows given in bands and backwards. Specs the native writers do not map are left to the codec
// (nullptr, no error), never written differently.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include <Imath/half.h>

#include "graph/domain.h"
#include "nodes/io/heightfield_file.h"
#include "nodes/io/image_codec.h"
#include "nodes/io/image_file.h"
#include "nodes/io/native/native_image_writers.h"

namespace orogen::test {
namespace {

// The bytes a writer writes, kept in memory; refuses every write that reaches past `limit` (a full disk).
class MemorySink final : public ImageByteSink {
 public:
  explicit MemorySink(std::int64_t limit = -1) : limit_(limit) {}
  bool pwrite(const void* data, std::size_t size, std::int64_t offset) override {
    const std::size_t end = static_cast<std::size_t>(offset) + size;
    if (limit_ >= 0 && end > static_cast<std::size_t>(limit_)) return false;
    if (bytes.size() < end) bytes.resize(end);
    std::memcpy(bytes.data() + offset, data, size);
    return true;
  }
  std::int64_t size() const override { return static_cast<std::int64_t>(bytes.size()); }
  std::vector<unsigned char> bytes;

 private:
  std::int64_t limit_;
};

// Random finite samples of the spec's type (signs, zeros and fractions for the float types), rows packed.
std::vector<unsigned char> random_samples(const ImageWriteSpec& spec, unsigned seed) {
  const std::size_t count = static_cast<std::size_t>(spec.width) * spec.height * spec.channels;
  std::vector<unsigned char> bytes(count * pixel_type_size(spec.type));
  std::mt19937 rng(seed);
  for (std::size_t k = 0; k < count; ++k) {
    const float v = static_cast<float>(static_cast<int>(rng() % 20001) - 10000) / 7.0f;
    if (spec.type == PixelType::U8 || spec.type == PixelType::U16) {
      const auto u = static_cast<std::uint16_t>(k % 7 == 0 ? rng() : (k / 13) * 37);  // runs and noise
      std::memcpy(bytes.data() + pixel_type_size(spec.type) * k, &u, pixel_type_size(spec.type));
    } else if (spec.type == PixelType::F32) {
      std::memcpy(bytes.data() + 4 * k, &v, 4);
    } else if (spec.type == PixelType::Half) {
      const std::uint16_t bits = Imath::half(v).bits();
      std::memcpy(bytes.data() + 2 * k, &bits, 2);
    } else {
      const std::uint32_t u = rng();
      std::memcpy(bytes.data() + 4 * k, &u, 4);
    }
  }
  return bytes;
}

// `samples` written by `writer` in bands of `band` rows; backwards: each band given from its last row with a
// negative stride, as the height writers give a heightfield's rows north first.
void write_bands(ImageWriter& writer, const ImageWriteSpec& spec, const std::vector<unsigned char>& samples, int band,
                 bool backwards) {
  const std::size_t row = samples.size() / static_cast<std::size_t>(spec.height);
  std::vector<unsigned char> reversed(samples.size());
  for (int y = 0; y < spec.height; ++y)
    std::memcpy(reversed.data() + static_cast<std::size_t>(spec.height - 1 - y) * row,
                samples.data() + static_cast<std::size_t>(y) * row, row);
  for (int y0 = 0; y0 < spec.height; y0 += band) {
    const int y1 = std::min(y0 + band, spec.height);
    const bool ok = backwards ? writer.write_rows(y0, y1, reversed.data() + (spec.height - 1 - y0) * row,
                                                  -static_cast<std::ptrdiff_t>(row))
                              : writer.write_rows(y0, y1, samples.data() + y0 * row, static_cast<std::ptrdiff_t>(row));
    ASSERT_TRUE(ok) << writer.error();
  }
  ASSERT_TRUE(writer.close()) << writer.error();
}

// The native writer's file against the codec's for `spec`, written in several ways.
void expect_as_the_codec_writes(const ImageWriteSpec& spec, const std::string& what,
                                const std::string& extension = "exr") {
  SCOPED_TRACE(what);
  const std::vector<unsigned char> samples =
      random_samples(spec, static_cast<unsigned>(spec.width * 7 + spec.channels));
  MemorySink theirs;
  std::string error;
  auto codec = image_codec().create_writer("file." + extension, theirs, spec, error);
  ASSERT_TRUE(codec) << error;
  write_bands(*codec, spec, samples, spec.height, false);
  ASSERT_GT(theirs.bytes.size(), 100u);
  for (const int band : {1, 5, 16, spec.height})
    for (const bool backwards : {false, true}) {
      SCOPED_TRACE("bands of " + std::to_string(band) + (backwards ? " rows, backwards" : " rows"));
      MemorySink mine;
      auto native = create_native_image_writer(extension, mine, spec, error);
      ASSERT_TRUE(native) << "the native writer refused the spec: " << error;
      write_bands(*native, spec, samples, band, backwards);
      ASSERT_EQ(mine.bytes.size(), theirs.bytes.size());
      ASSERT_TRUE(mine.bytes == theirs.bytes) << "the files differ";
    }
}

TEST(NativeWriters, HeightsWriteAsTheCodecWrites) {
  const Domain domain = Domain::from_extent({-50.0, 20.0}, {1000.0, 750.0}, {37, 29});
  for (const std::string codec : {"none", "zip", "piz", "pxr24"})
    for (const int level : {-1, 0, 1, 6, 9}) {
      HeightfieldWriteOptions options;
      options.format = HeightFormat::Exr;
      options.exr_compression = codec;
      options.compression_level = level;
      expect_as_the_codec_writes(heightfield_image_spec(domain, options, std::nullopt),
                                 codec + " at level " + std::to_string(level));
    }
}

TEST(NativeWriters, ImagesWriteAsTheCodecWrites) {
  for (const int channels : {1, 2, 3, 4, 5})
    for (const int level : {-1, 0, 3}) {
      ImageWriteOptions options;
      options.format = ImageFormat::Exr;
      options.compression_level = level;
      expect_as_the_codec_writes(image_file_spec(23, 19, channels, {}, options),
                                 std::to_string(channels) + " channels at level " + std::to_string(level));
    }
  // Channel names of the image's own, in an order that is not OpenEXR's (it sorts them by name).
  ImageWriteOptions options;
  options.format = ImageFormat::Exr;
  expect_as_the_codec_writes(image_file_spec(17, 33, 3, {"wetness", "flow", "Z"}, options), "named channels");
}

TEST(NativeWriters, OtherSampleTypesCodecsAndADateWriteAsTheCodecWrites) {
  for (const PixelType type : {PixelType::Half, PixelType::F32, PixelType::U32})
    for (const std::string compression : {"none", "rle", "zips", "zips:2", "zip:9", "piz", "b44", "b44a"}) {
      ImageWriteSpec spec;
      spec.width = 29;
      spec.height = 40;
      spec.channels = 2;
      spec.type = type;
      spec.channel_names = {"Y", "A"};
      spec.set("Software", "Orogen");
      spec.set("DateTime", "2026:12:07 05:30:00");
      spec.set("compression", compression);
      expect_as_the_codec_writes(spec, compression + " of type " + std::to_string(pixel_type_size(type)));
    }
}

TEST(NativeWriters, PngHeightsWriteAsTheCodecWrites) {
  const Domain domain = Domain::from_extent({-50.0, 20.0}, {1000.0, 750.0}, {37, 29});
  for (const int level : {-1, 0, 1, 3, 6, 9}) {
    HeightfieldWriteOptions options;
    options.format = HeightFormat::Png16;
    options.compression_level = level;
    expect_as_the_codec_writes(heightfield_image_spec(domain, options, HeightRange{-12.5, 1040.25}),
                               "16-bit heights at level " + std::to_string(level), "png");
  }
}

TEST(NativeWriters, PngImagesWriteAsTheCodecWrites) {
  for (const ImageFormat format : {ImageFormat::Png8, ImageFormat::Png16})
    for (const int channels : {1, 2, 3, 4})
      for (const bool srgb : {true, false})
        for (const int level : {-1, 0, 2, 6}) {
          ImageWriteOptions options;
          options.format = format;
          options.srgb = srgb;
          options.compression_level = level;
          expect_as_the_codec_writes(image_file_spec(23, 19, channels, {}, options),
                                     std::to_string(channels) + " channels of " +
                                         (format == ImageFormat::Png8 ? "8" : "16") + " bits, " +
                                         (srgb ? "sRGB" : "linear") + ", level " + std::to_string(level),
                                     "png");
        }
}

TEST(NativeWriters, SpecsItDoesNotMapAreLeftToTheCodec) {
  const auto refused = [](const ImageWriteSpec& spec, const std::string& extension = "exr") {
    MemorySink sink;
    std::string error = "stale";
    const bool made = create_native_image_writer(extension, sink, spec, error) != nullptr;
    EXPECT_TRUE(error.empty()) << error;
    if (!made) EXPECT_TRUE(sink.bytes.empty()) << "a refused spec wrote bytes";
    return !made;
  };
  ImageWriteSpec spec;
  spec.width = spec.height = 8;
  spec.channels = 1;
  spec.channel_names = {"Y"};
  EXPECT_FALSE(refused(spec));
  EXPECT_TRUE(refused(spec, "png"));  // float samples
  EXPECT_TRUE(refused(spec, "tif"));
  ImageWriteSpec png = spec;
  png.type = PixelType::U8;
  EXPECT_FALSE(refused(png, "png"));
  ImageWriteSpec dated = png;
  dated.set("DateTime", "2026:12:07 05:30:00");  // a tIME chunk, which the codec makes its own way
  EXPECT_TRUE(refused(dated, "png"));
  ImageWriteSpec premultiplied = png;
  premultiplied.channels = 4;
  premultiplied.alpha_channel = 3;
  EXPECT_TRUE(refused(premultiplied, "png"));  // the codec would divide the colour by the alpha
  ImageWriteSpec five = png;
  five.channels = 5;
  EXPECT_TRUE(refused(five, "png"));
  for (const std::string compression : {"dwaa", "zip:0", "zip:10", "zip:", "piz:3", "jpeg"}) {
    ImageWriteSpec other = spec;
    other.set("compression", compression);
    EXPECT_TRUE(refused(other)) << compression;
  }
  ImageWriteSpec attribute = spec;
  attribute.set("orogen:height_min", "3");
  EXPECT_TRUE(refused(attribute));
  ImageWriteSpec number = spec;
  number.set("Software", 3);
  EXPECT_TRUE(refused(number));
  ImageWriteSpec u16 = spec;
  u16.type = PixelType::U16;
  EXPECT_TRUE(refused(u16));
  ImageWriteSpec twins = spec;
  twins.channels = 2;
  twins.channel_names = {"Y", "Y"};
  EXPECT_TRUE(refused(twins));
  ImageWriteSpec unnamed = spec;
  unnamed.channel_names.clear();
  EXPECT_TRUE(refused(unnamed));
}

// A full disk fails the write or the close with a message, never a file that looks whole; rows out of order
// and a file closed early are refused.
TEST(NativeWriters, FailuresAreReported) {
  for (const std::string extension : {"exr", "png"}) {
    SCOPED_TRACE(extension);
    ImageWriteSpec spec;
    spec.width = 64;
    spec.height = 48;
    spec.channels = 1;
    spec.type = extension == "exr" ? PixelType::F32 : PixelType::U16;
    spec.channel_names = {"Y"};
    if (extension == "exr") spec.set("compression", "none");
    const std::vector<unsigned char> samples = random_samples(spec, 5);
    const std::size_t row = samples.size() / static_cast<std::size_t>(spec.height);
    const auto write_all = [&](ImageByteSink& sink, std::string& error) {
      auto writer = create_native_image_writer(extension, sink, spec, error);
      if (!writer) return false;
      bool ok = true;
      for (int y = 0; y < spec.height && ok; y += 8)
        ok = writer->write_rows(y, y + 8, samples.data() + y * row, static_cast<std::ptrdiff_t>(row));
      ok = ok && writer->close();
      error = writer->error();
      return ok;
    };
    MemorySink whole;
    std::string error;
    ASSERT_TRUE(write_all(whole, error)) << error;
    const auto size = static_cast<std::int64_t>(whole.bytes.size());
    for (const std::int64_t limit : {std::int64_t{10}, size / 3, 2 * size / 3, size - 1}) {
      SCOPED_TRACE("disk full after " + std::to_string(limit) + " of " + std::to_string(size) + " bytes");
      MemorySink sink(limit);
      EXPECT_FALSE(write_all(sink, error));
      EXPECT_FALSE(error.empty());
    }
    MemorySink sink;
    auto writer = create_native_image_writer(extension, sink, spec, error);
    ASSERT_TRUE(writer) << error;
    EXPECT_FALSE(writer->write_rows(8, 16, samples.data() + 8 * row, static_cast<std::ptrdiff_t>(row)));
    EXPECT_NE(writer->error().find("out of order"), std::string::npos) << writer->error();
    ASSERT_TRUE(writer->write_rows(0, 8, samples.data(), static_cast<std::ptrdiff_t>(row))) << writer->error();
    EXPECT_FALSE(writer->close());
    EXPECT_NE(writer->error().find("8 of 48 rows"), std::string::npos) << writer->error();
    // Closed is closed, whole or not.
    EXPECT_FALSE(writer->write_rows(8, 16, samples.data() + 8 * row, static_cast<std::ptrdiff_t>(row)));
    EXPECT_NE(writer->error().find("closed"), std::string::npos) << writer->error();
    EXPECT_FALSE(writer->close());
  }
}

}  // namespace
}  // namespace orogen::test
