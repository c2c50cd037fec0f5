// ReadHeightfield streams the file onto the domain (read_heightfield_onto): a band of rows at a time, keeping
// only the two rows each target row interpolates. The result must be the one the whole-file path gives (read,
// placed on the image's lattice, resampled bilinear), bit for bit, for every format, tiled files, placements
// that cover part of the image or reach beyond it, and domains finer or coarser than the file. (Its memory:
// tests/test_peak_memory.cpp.)
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <OpenImageIO/imageio.h>

#include "evaluator/run_node.h"
#include "graph/heightfield.h"
#include "nodes/common/resample.h"
#include "nodes/io/heightfield_file.h"
#include "support/test_paths.h"

namespace orogen {
namespace {

namespace fs = std::filesystem;

Heightfield ridges(int side) {
  Heightfield h(Domain::from_extent({0, 0}, {1, 1}, {side, side}));
  for (int j = 0; j < side; ++j)
    for (int i = 0; i < side; ++i)
      h.at(i, j) = static_cast<float>(300.0 + 250.0 * std::sin(0.037 * i) * std::cos(0.051 * j) + 0.01 * i * j);
  return h;
}

fs::path write(const Heightfield& h, const fs::path& path, HeightFormat format) {
  HeightfieldWriteOptions o;
  o.format = format;
  o.range = HeightRange{-100.0, 700.0};
  write_heightfield_file(h, path, o);
  return path;
}

// A tiled float TIFF (written with OpenImageIO directly; Orogen's writer writes strips).
fs::path write_tiled_tiff(const Heightfield& h, const fs::path& path) {
  OIIO::ImageSpec spec(h.width(), h.height(), 1, OIIO::TypeDesc::FLOAT);
  spec.tile_width = 64;
  spec.tile_height = 32;
  auto out = OIIO::ImageOutput::create(path.string());
  EXPECT_TRUE(out && out->open(path.string(), spec));
  std::vector<float> flipped(h.data.size());
  for (int r = 0; r < h.height(); ++r)
    std::memcpy(flipped.data() + static_cast<std::size_t>(r) * static_cast<std::size_t>(h.width()),
                h.row(h.height() - 1 - r).data(), static_cast<std::size_t>(h.width()) * sizeof(float));
  EXPECT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, flipped.data()));
  out->close();
  return path;
}

void expect_identical(const fs::path& file, const HeightfieldReadOptions& options, const Domain& target) {
  const Heightfield whole = resample_bilinear(raster_to_heightfield(read_height_raster(file), options), target);
  int rows = 0;
  const Heightfield streamed = read_heightfield_onto(file, 0, options, target, [&](int done) { rows = done; });
  EXPECT_EQ(rows, target.height());
  ASSERT_EQ(streamed.data.size(), whole.data.size());
  std::size_t differing = 0;
  for (std::size_t k = 0; k < whole.data.size(); ++k)
    differing += std::memcmp(&streamed.data[k], &whole.data[k], sizeof(float)) != 0;
  EXPECT_EQ(differing, 0u) << file.filename() << " onto " << target.describe();
}

TEST(ReadHeightfieldStream, EqualsTheWholeFileReadBitForBit) {
  const fs::path dir = test::scratch_dir("read-stream");
  const Heightfield big = ridges(2049);
  const Heightfield odd = ridges(333);
  const std::vector<fs::path> files = {
      write(big, dir / "big.png", HeightFormat::Png16), write(odd, dir / "odd.exr", HeightFormat::Exr),
      write(odd, dir / "odd.tif", HeightFormat::Tiff),  write(odd, dir / "odd.r16", HeightFormat::Raw16),
      write_tiled_tiff(odd, dir / "tiled.tif"),
  };
  const Domain coarse = Domain::from_extent({0, 0}, {2560, 2560}, {257, 257});
  const Domain fine = Domain::from_extent({0, 0}, {2560, 1900}, {601, 450});
  HeightfieldReadOptions spans;  // the image spans the domain (ReadHeightfield's default)
  spans.origin = {0, 0};
  spans.size = {2560, 2560};
  HeightfieldReadOptions part;  // the domain covers part of the image and reaches beyond its edge
  part.origin = {-700, 300};
  part.size = {2000, 5000};
  part.range = HeightRange{10.0, 20.0};
  part.use_file_mapping = false;
  for (const fs::path& file : files)
    for (const HeightfieldReadOptions& options : {spans, part}) {
      expect_identical(file, options, coarse);
      expect_identical(file, options, fine);
    }
}

TEST(ReadHeightfieldStream, TheNodeGivesTheWholeFileResult) {
  const fs::path dir = test::scratch_dir("read-stream-node");
  const fs::path png = write(ridges(700), dir / "r.png", HeightFormat::Png16);
  const Domain d = Domain::from_extent({100, -50}, {5000, 3000}, {129, 77});
  const auto run = run_node("ReadHeightfield", d, {{"path", png.string()}});
  HeightfieldReadOptions o;
  o.origin = d.min_corner();
  o.size = d.size();
  const Heightfield whole = resample_bilinear(raster_to_heightfield(read_height_raster(png), o), d);
  EXPECT_EQ(std::memcmp(run.get<Heightfield>()->data.data(), whole.data.data(), whole.data.size() * sizeof(float)), 0);
}

TEST(ReadHeightfieldStream, DamagedFilesAreFileErrors) {
  const fs::path dir = test::scratch_dir("read-stream-damaged");
  const fs::path png = write(ridges(300), dir / "t.png", HeightFormat::Png16);
  const auto size = fs::file_size(png);
  fs::resize_file(png, size / 2);  // the header is intact, half the rows are missing
  HeightfieldReadOptions o;
  o.size = {100, 100};
  EXPECT_THROW(read_heightfield_onto(png, 0, o, Domain::from_extent({0, 0}, {100, 100}, {64, 64})), FileError);
  EXPECT_THROW(read_heightfield_onto(png, 1, o, Domain::from_extent({0, 0}, {100, 100}, {64, 64})), FileError);
}

}  // namespace
}  // namespace orogen
