// Readers and writers: round trips per format, byte layout of RAW, resampling on read, clear errors, atomic
// replacement when a write fails part-way, and the output-path rule.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <thread>

#include <gtest/gtest.h>
#include <OpenImageIO/half.h>
#include <OpenImageIO/imageio.h>
#include <nlohmann/json.hpp>

#include "evaluator/run_node.h"
#include "graph/atomic_file.h"
#include "graph/exec_context.h"
#include "graph/registry.h"
#include "nodes/io/heightfield_file.h"
#include "nodes/io/image_file.h"
#include "nodes/io/points_file.h"
#include "support/run_process.h"
#include "support/test_paths.h"

namespace orogen {
namespace {

namespace fs = std::filesystem;

// A field with values of every magnitude and sign, so a lossy path would show.
HeightfieldPtr varied_field(const Domain& d) {
  auto h = std::make_shared<Heightfield>(d);
  for (int j = 0; j < d.height(); ++j)
    for (int i = 0; i < d.width(); ++i)
      h->at(i, j) = static_cast<float>(300.0 * std::sin(0.37 * i + 0.11 * j * j) + 1e-3 * i - 7.25 * j) *
                    (i % 5 == 0 ? 1e-4f : 1.0f);
  return h;
}

HeightfieldPtr ramp_field(const Domain& d, double ax, double ay, double c) {
  auto h = std::make_shared<Heightfield>(d);
  for (int j = 0; j < d.height(); ++j)
    for (int i = 0; i < d.width(); ++i) h->at(i, j) = static_cast<float>(ax * d.x(i) + ay * d.y(j) + c);
  return h;
}

std::string read_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::vector<fs::path> temporaries_in(const fs::path& dir) {
  std::vector<fs::path> found;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (is_temporary_name(e.path().filename().string())) found.push_back(e.path());
  return found;
}

// Runs a writer node through an ExecContext (like the evaluator does), returning the files it recorded.
// `on_progress` sees every progress report; `cancel` is the run's cancel token.
std::vector<fs::path> run_writer(const std::string& type_name, const std::map<std::string, ParamValue>& params,
                                 const std::map<std::string, PortValue>& inputs, const OutputPolicy& policy,
                                 std::function<void(double)> on_progress = {}, const CancelToken* cancel = nullptr) {
  const NodeType* type = NodeRegistry::instance().find(type_name);
  EXPECT_NE(type, nullptr);
  std::vector<ParamValue> values;
  for (const auto& decl : type->params) {
    const auto it = params.find(decl.name);
    values.push_back(it == params.end() ? decl.default_value : it->second);
  }
  std::vector<PortValue> in(type->inputs.size());
  for (const auto& [name, v] : inputs) in[static_cast<std::size_t>(type->input_index(name))] = v;
  ExecContext ctx(*type, "writer", Domain{}, std::move(in), std::move(values));
  ctx.set_output_policy(policy);
  ctx.set_progress_callback(std::move(on_progress));
  ctx.set_cancel_token(cancel);
  type->execute(ctx);
  return ctx.written_files();
}

class IoTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::scratch_dir("io");
    policy_.output_dir = dir_ / "out";
  }
  // Writes `h` with WriteHeightfield to out/<name>; returns the file.
  fs::path write_height(const HeightfieldPtr& h, const std::string& name,
                        std::map<std::string, ParamValue> params = {}) {
    params["path"] = name;
    const auto files = run_writer("WriteHeightfield", params, {{"in", h}}, policy_);
    // 16-bit formats also write their mapping beside the image (<file>.json).
    for (const auto& f : files)
      if (f.extension() != ".json") return f;
    ADD_FAILURE() << "no file written";
    return {};
  }
  HeightfieldPtr read_height(const fs::path& file, const Domain& d, std::map<std::string, ParamValue> params = {}) {
    params["path"] = file.string();
    if (!params.count("origin")) params["origin"] = d.min_corner();
    if (!params.count("size")) params["size"] = d.size();
    return run_node("ReadHeightfield", d, params).get<Heightfield>();
  }
  fs::path dir_;
  OutputPolicy policy_;
};

// EXR heights: every codec reads back (the lossless ones exactly, pxr24 to a 24-bit float's precision), and
// the default stores the floats uncompressed (payload plus a small header).
TEST_F(IoTest, ExrCodecsRoundTripAndTheDefaultStores) {
  const Domain d = Domain::from_extent({0, 0}, {640, 370}, {129, 37});
  auto field = std::make_shared<Heightfield>(d);
  for (int j = 0; j < d.height(); ++j)
    for (int i = 0; i < d.width(); ++i)
      field->at(i, j) = static_cast<float>(700.0 * std::sin(d.x(i) / 47.0) * std::cos(d.y(j) / 29.0) + 0.37 * i);
  const HeightfieldPtr h = field;
  std::map<std::string, std::uintmax_t> sizes;
  for (const std::string codec : {"default", "none", "zip", "piz", "pxr24"}) {
    std::map<std::string, ParamValue> params;
    if (codec != "default") params["exr_compression"] = codec;
    const fs::path file = write_height(h, codec + ".exr", params);
    sizes[codec] = fs::file_size(file);
    const auto back = read_height(file, d);
    for (std::size_t k = 0; k < h->data.size(); ++k) {
      if (codec == "pxr24")
        ASSERT_NEAR(back->data[k], h->data[k], std::abs(h->data[k]) * 0x1p-15f) << k;  // 15 stored mantissa bits
      else
        ASSERT_EQ(back->data[k], h->data[k]) << codec << " " << k;
    }
  }
  const std::uintmax_t payload = 4u * d.sample_count();
  EXPECT_EQ(sizes["default"], sizes["none"]);
  EXPECT_GT(sizes["none"], payload);
  EXPECT_LT(sizes["none"], payload + 4096) << "header and offset table only";
  EXPECT_LT(sizes["pxr24"], sizes["none"] * 4 / 5) << "pxr24 drops a byte of every float";
  EXPECT_NE(sizes["zip"], sizes["none"]);
  EXPECT_NE(sizes["piz"], sizes["none"]);
}

// Identical inputs give identical files: no time of writing in EXR and TIFF headers, or SOURCE_DATE_EPOCH.
TEST_F(IoTest, HeadersCarryNoTimeOfWritingButSourceDateEpoch) {
  const Domain d = Domain::from_extent({0, 0}, {64, 48}, {17, 13});
  const auto h = varied_field(d);
  auto image = std::make_shared<Image>(d, 3, 0.25f);
  auto bytes = [](const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  auto write_all = [&](const std::string& prefix) {
    write_height(h, prefix + "h.exr");
    write_height(h, prefix + "h.tif");
    run_writer("WriteImage", {{"path", prefix + "c.exr"}}, {{"in", ImagePtr(image)}}, policy_);
    run_writer("WriteImage", {{"path", prefix + "c.tif"}}, {{"in", ImagePtr(image)}}, policy_);
  };
  ::unsetenv("SOURCE_DATE_EPOCH");
  write_all("a_");
  std::this_thread::sleep_for(std::chrono::milliseconds(1100));  // a time of writing would now differ
  write_all("b_");
  for (const char* f : {"h.exr", "h.tif", "c.exr", "c.tif"}) {
    const auto a = bytes(policy_.output_dir / (std::string("a_") + f));
    ASSERT_FALSE(a.empty()) << f;
    EXPECT_TRUE(a == bytes(policy_.output_dir / (std::string("b_") + f))) << f;
    EXPECT_EQ(a.find(":20"), std::string::npos) << f << " has a date";  // "YYYY:MM:DD", e.g. 2026:12:01
  }
  ::setenv("SOURCE_DATE_EPOCH", "86400", 1);
  write_all("e_");
  ::unsetenv("SOURCE_DATE_EPOCH");
  for (const char* f : {"h.exr", "h.tif", "c.exr", "c.tif"})
    EXPECT_NE(bytes(policy_.output_dir / (std::string("e_") + f)).find("1970:01:02 00:00:00"), std::string::npos) << f;
}

TEST_F(IoTest, ExrRoundTripIsBitExact) {
  const Domain d = Domain::from_extent({100, -50}, {300, 200}, {37, 23});
  const auto h = varied_field(d);
  const fs::path file = write_height(h, "sub/dir/height.exr");  // parent directories are created
  EXPECT_EQ(file, policy_.output_dir / "sub/dir/height.exr");
  ASSERT_TRUE(fs::exists(file));
  const auto back = read_height(file, d);
  ASSERT_EQ(back->domain, d);
  for (std::size_t k = 0; k < h->data.size(); ++k)
    ASSERT_EQ(std::bit_cast<std::uint32_t>(back->data[k]), std::bit_cast<std::uint32_t>(h->data[k])) << k;
  EXPECT_EQ(read_height_raster(file).format, "float");
  EXPECT_TRUE(temporaries_in(dir_).empty());
}

TEST_F(IoTest, TiffRoundTripIsBitExact) {
  const Domain d = Domain::from_extent({0, 0}, {64, 48}, {17, 13});
  const auto h = varied_field(d);
  const auto back = read_height(write_height(h, "height.tif"), d);
  EXPECT_EQ(back->data, h->data);
  const auto raster = read_height_raster(policy_.output_dir / "height.tif");
  EXPECT_EQ(raster.format, "float");
  EXPECT_EQ(raster.width, 17);
  EXPECT_EQ(raster.height, 13);
}

std::vector<float> read_pixels_float(const fs::path& file, int& w, int& h, int& n);
std::vector<std::uint8_t> read_pixels_u8(const fs::path& file, int& w, int& h, int& n);

// Blocks of scanlines: a height that is not a multiple of the block (here 37 rows of 16, 16 and 5), every
// format, every compression level reads back the same, and the level changes the file.
TEST_F(IoTest, ChunkedWritesAndCompressionLevels) {
  const Domain d = Domain::from_extent({0, 0}, {640, 370}, {129, 37});
  // Smooth and on a 1/64 m grid: compressible, so the levels give different files.
  auto smooth = std::make_shared<Heightfield>(d);
  for (int j = 0; j < d.height(); ++j)
    for (int i = 0; i < d.width(); ++i)
      smooth->at(i, j) =
          static_cast<float>(std::round(64.0 * 100.0 * std::sin(d.x(i) / 50.0) * std::cos(d.y(j) / 30.0)) / 64.0);
  const HeightfieldPtr h = smooth;
  for (const std::string ext : {".exr", ".tif", ".png"}) {
    std::map<int, std::uintmax_t> sizes;
    for (int level : {0, 1, 9}) {
      const std::string name = "level" + std::to_string(level) + ext;
      const fs::path file =
          write_height(h, name, {{"compression_level", std::int64_t(level)}, {"exr_compression", std::string("zip")}});
      sizes[level] = fs::file_size(file);
      const auto back = read_height(file, d);
      for (std::size_t k = 0; k < h->data.size(); ++k) {
        if (ext == ".png") {
          const auto range = data_range(*h);
          ASSERT_NEAR(back->data[k], h->data[k], 0.5 * (range.max - range.min) / 65535 + 1e-4) << name << " " << k;
        } else {
          ASSERT_EQ(back->data[k], h->data[k]) << name << " " << k;
        }
      }
    }
    EXPECT_GT(sizes[0], sizes[1]) << ext << ": level 0 stores, 1 compresses";
    EXPECT_NE(sizes[1], sizes[9]) << ext << ": the level reaches the compressor";
  }
  // Images too: 8-bit PNG and float EXR, north row first across block boundaries.
  auto img = std::make_shared<Image>(d, 3);
  for (std::size_t k = 0; k < img->data.size(); ++k) img->data[k] = static_cast<float>((k * 7919 % 1000) / 1000.0);
  for (const std::string name : {"c0.exr", "c9.png"}) {
    const std::int64_t level = name[1] == '0' ? 0 : 9;
    const auto files = run_writer("WriteImage", {{"path", name}, {"srgb", false}, {"compression_level", level}},
                                  {{"in", ImagePtr(img)}}, policy_);
    int w = 0, hh = 0, n = 0;
    if (name == "c0.exr") {
      const auto px = read_pixels_float(files.at(0), w, hh, n);
      for (int r = 0; r < hh; ++r)
        for (int i = 0; i < w; ++i)
          for (int c = 0; c < n; ++c)
            ASSERT_EQ(px[static_cast<std::size_t>((r * w + i) * n + c)], img->pixel(i, hh - 1 - r)[c]);
    } else {
      const auto px = read_pixels_u8(files.at(0), w, hh, n);
      for (int r = 0; r < hh; ++r)
        for (int i = 0; i < w; ++i)
          for (int c = 0; c < n; ++c)
            ASSERT_EQ(px[static_cast<std::size_t>((r * w + i) * n + c)],
                      std::lround(img->pixel(i, hh - 1 - r)[c] * 255.0));
    }
  }
}

TEST_F(IoTest, Png16RoundTripWithinOneQuantisationStep) {
  const Domain d = Domain::from_extent({-20, 30}, {500, 400}, {41, 33});
  const auto h = varied_field(d);
  const HeightRange range = data_range(*h);
  const double step = (range.max - range.min) / 65535.0;
  const fs::path file = write_height(h, "height.png");
  const auto raster = read_height_raster(file);
  EXPECT_EQ(raster.format, "uint16");
  ASSERT_TRUE(raster.file_mapping.has_value());  // the mapping used is in the file's metadata
  EXPECT_EQ(*raster.file_mapping, range);
  // Decoy params: the file's mapping takes precedence.
  const auto back = read_height(file, d, {{"height_min", -1.0}, {"height_max", 1.0}});
  double worst = 0;
  for (std::size_t k = 0; k < h->data.size(); ++k)
    worst = std::max(worst, std::abs(double(back->data[k]) - h->data[k]));
  EXPECT_LE(worst, step);
  EXPECT_GT(worst, 0.0);  // it really was quantised
  // The extremes map to 0 and 65535 exactly.
  EXPECT_EQ(*std::min_element(raster.values.begin(), raster.values.end()), 0.0);
  EXPECT_EQ(*std::max_element(raster.values.begin(), raster.values.end()), 1.0);
  // Without the file's mapping the params apply.
  const auto by_params = read_height(file, d, {{"height_min", 0.0}, {"height_max", 1.0}, {"use_file_mapping", false}});
  for (std::size_t k = 0; k < h->data.size(); ++k)
    ASSERT_NEAR(by_params->data[k], (h->data[k] - range.min) / (range.max - range.min), 1.0 / 65535.0);
}

TEST_F(IoTest, Png16FixedRangeClampsAndRecordsTheRange) {
  const Domain d = Domain::from_extent({0, 0}, {100, 100}, {21, 21});
  const auto h = ramp_field(d, 1.0, 0.0, -25.0);  // -25 .. 75
  const fs::path file =
      write_height(h, "fixed.png", {{"range", std::string("fixed")}, {"height_min", 0.0}, {"height_max", 50.0}});
  const auto raster = read_height_raster(file);
  ASSERT_TRUE(raster.file_mapping.has_value());
  EXPECT_EQ(*raster.file_mapping, (HeightRange{0.0, 50.0}));
  const auto back = read_height(file, d);
  for (int j = 0; j < 21; ++j)
    for (int i = 0; i < 21; ++i)
      ASSERT_NEAR(back->at(i, j), std::clamp(h->at(i, j), 0.0f, 50.0f), 50.0 / 65535.0) << i << "," << j;
}

TEST_F(IoTest, Raw16RoundTripWithinOneQuantisationStep) {
  const Domain d = Domain::from_extent({0, 0}, {1000, 1000}, {65, 65});  // RAW files are square
  const auto h = varied_field(d);
  const HeightRange range = data_range(*h);
  const fs::path file = write_height(h, "height.r16");
  EXPECT_EQ(fs::file_size(file), 65u * 65u * 2u);
  // RAW carries no metadata: the reader is told the range.
  const auto back = read_height(file, d, {{"height_min", range.min}, {"height_max", range.max}});
  for (std::size_t k = 0; k < h->data.size(); ++k)
    ASSERT_LE(std::abs(double(back->data[k]) - h->data[k]), (range.max - range.min) / 65535.0) << k;
}

TEST_F(IoTest, Raw16ByteLayoutIsLittleEndianNorthRowFirst) {
  // 3 x 2 samples, fixed range 0..65535 m so the code equals the height.
  const Domain d = Domain::from_extent({0, 0}, {2, 1}, {3, 2});
  auto h = std::make_shared<Heightfield>(d);
  h->at(0, 0) = 0x0102;  // south row (y = 0)
  h->at(1, 0) = 0x0304;
  h->at(2, 0) = 0xfffe;
  h->at(0, 1) = 0x0a0b;  // north row (y = 1)
  h->at(1, 1) = 0;
  h->at(2, 1) = 65535;
  const fs::path file =
      write_height(h, "layout.raw", {{"range", std::string("fixed")}, {"height_min", 0.0}, {"height_max", 65535.0}});
  const std::string bytes = read_bytes(file);
  const std::string expected(
      "\x0b\x0a\x00\x00\xff\xff"  // north row first, west to east, low byte first
      "\x02\x01\x04\x03\xfe\xff",
      12);
  EXPECT_EQ(bytes, expected);
}

TEST_F(IoTest, Reads8BitPngAndChosenChannel) {
  // An RGB 8-bit PNG written by OpenImageIO directly: R = column * 10, G = 255 - row * 20, B = 7.
  const fs::path file = dir_ / "rgb.png";
  const int w = 12, hgt = 9;
  std::vector<std::uint8_t> px(static_cast<std::size_t>(w * hgt * 3));
  for (int r = 0; r < hgt; ++r)
    for (int c = 0; c < w; ++c) {
      auto* p = &px[static_cast<std::size_t>((r * w + c) * 3)];
      p[0] = static_cast<std::uint8_t>(c * 10);
      p[1] = static_cast<std::uint8_t>(255 - r * 20);
      p[2] = 7;
    }
  {
    auto out = OIIO::ImageOutput::create(file.string());
    ASSERT_TRUE(out);
    ASSERT_TRUE(out->open(file.string(), OIIO::ImageSpec(w, hgt, 3, OIIO::TypeDesc::UINT8)));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, px.data()));
    out->close();
  }
  const Domain d = Domain::from_extent({0, 0}, {110, 80}, {w, hgt});                      // pixel centres every 10 m
  const auto red = read_height(file, d, {{"height_min", 100.0}, {"height_max", 355.0}});  // 1 m per code
  const auto green = read_height(file, d, {{"channel", std::int64_t(1)}, {"height_min", 0.0}, {"height_max", 255.0}});
  for (int j = 0; j < hgt; ++j)
    for (int i = 0; i < w; ++i) {
      EXPECT_NEAR(red->at(i, j), 100.0 + i * 10, 1e-4);
      EXPECT_NEAR(green->at(i, j), 255.0 - (hgt - 1 - j) * 20, 1e-4);  // file row 0 is the north row
    }
  EXPECT_THROW(read_height(file, d, {{"channel", std::int64_t(3)}}), NodeError);
}

TEST_F(IoTest, ReadsHalfFloatExrExactly) {
  // Every binary16 bit pattern in a half EXR (written by OpenImageIO directly) reads as Imath's value of it:
  // the reader decodes halves itself (OpenImageIO lives in the image codec module).
  const fs::path file = dir_ / "half.exr";
  const int side = 256;
  std::vector<std::uint16_t> bits(static_cast<std::size_t>(side * side));
  for (std::size_t k = 0; k < bits.size(); ++k) bits[k] = static_cast<std::uint16_t>(k);
  {
    auto out = OIIO::ImageOutput::create(file.string());
    ASSERT_TRUE(out);
    OIIO::ImageSpec spec(side, side, 1, OIIO::TypeDesc::HALF);
    spec.attribute("compression", "none");
    ASSERT_TRUE(out->open(file.string(), spec));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::HALF, bits.data()));
    out->close();
  }
  const HeightRaster raster = read_height_raster(file);
  EXPECT_EQ(raster.format, "half");
  EXPECT_FALSE(raster.unsigned_integer);
  ASSERT_EQ(raster.values.size(), bits.size());
  for (std::size_t k = 0; k < bits.size(); ++k) {
    Imath::half value;
    value.setBits(bits[k]);
    const double expected = static_cast<float>(value);
    if (std::isnan(expected))
      EXPECT_TRUE(std::isnan(raster.values[k])) << k;
    else
      ASSERT_EQ(raster.values[k], expected) << "bits " << k;
  }
  // The streaming reader decodes the same way (heightfield row j is file row side - 1 - j).
  HeightfieldReadOptions o;
  o.size = {255.0, 255.0};
  const Heightfield h = read_heightfield_onto(file, 0, o, Domain::from_extent({0, 0}, {255, 255}, {side, side}));
  for (const auto [i, j] : {std::pair{7, 200}, std::pair{200, side - 1}, std::pair{3, 40}}) {
    Imath::half value;
    value.setBits(static_cast<std::uint16_t>((side - 1 - j) * side + i));
    EXPECT_EQ(h.at(i, j), static_cast<float>(value)) << i << ", " << j;
  }
}

TEST_F(IoTest, ReadResamplesOntoAnotherDomainAndLinearStaysLinear) {
  // A ramp on a 33 x 17 image over [0, 320] x [0, 160]; read onto a finer, shifted domain.
  const Domain img = Domain::from_extent({0, 0}, {320, 160}, {33, 17});
  const auto h = ramp_field(img, 0.25, -0.5, 40.0);
  const fs::path file = write_height(h, "ramp.exr");
  const Domain target = Domain::from_extent({-40, 10}, {400, 100}, {101, 26});
  const auto back = read_height(file, target, {{"origin", glm::dvec2(0, 0)}, {"size", glm::dvec2(320, 160)}});
  ASSERT_EQ(back->domain, target);
  for (int j = 0; j < target.height(); ++j)
    for (int i = 0; i < target.width(); ++i) {
      const double x = std::clamp(target.x(i), 0.0, 320.0), y = target.y(j);  // clamped outside the image
      ASSERT_NEAR(back->at(i, j), 0.25 * x - 0.5 * y + 40.0, 1e-4) << i << "," << j;
    }
  // A shifted image rectangle moves the terrain with it.
  const auto moved = read_height(file, img, {{"origin", glm::dvec2(40, 0)}, {"size", glm::dvec2(320, 160)}});
  for (int j = 0; j < img.height(); ++j)
    for (int i = 4; i < img.width(); ++i) ASSERT_NEAR(moved->at(i, j), h->at(i - 4, j), 1e-4);
}

TEST_F(IoTest, ReadErrorsAreClear) {
  const Domain d = Domain::from_extent({0, 0}, {10, 10}, {4, 4});
  try {
    read_height(dir_ / "no_such.exr", d);
    FAIL() << "no error for a missing file";
  } catch (const NodeError& e) {
    EXPECT_NE(std::string(e.what()).find("no_such.exr"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("does not exist"), std::string::npos) << e.what();
  }
  { std::ofstream(dir_ / "garbage.png") << "this is not a PNG"; }
  EXPECT_THROW(read_height(dir_ / "garbage.png", d), NodeError);
  {
    std::ofstream(dir_ / "odd.raw", std::ios::binary) << std::string(6, '\0');  // 3 samples: not square
  }
  EXPECT_THROW(read_height(dir_ / "odd.raw", d), NodeError);
  EXPECT_THROW(run_node("ReadHeightfield", d, {}), NodeError);  // no path
}

// Only the reader the extension names is tried: a PNG renamed .tif is refused (with the format named) rather
// than handed to every plugin OpenImageIO has, which would widen what a damaged file can reach.
TEST_F(IoTest, ReadUsesTheReaderTheExtensionNames) {
  const Domain d = Domain::from_extent({0, 0}, {10, 10}, {9, 9});
  const fs::path png = write_height(varied_field(d), "real.png");
  const fs::path renamed = dir_ / "renamed.tif";
  fs::copy_file(png, renamed, fs::copy_options::overwrite_existing);
  EXPECT_NO_THROW(read_height(png, d));
  try {
    read_height(renamed, d);
    FAIL() << "a PNG named .tif was read";
  } catch (const NodeError& e) {
    EXPECT_NE(std::string(e.what()).find("renamed.tif"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("extension"), std::string::npos) << e.what();
  }
}

TEST_F(IoTest, ReadPathIsRelativeToTheCurrentDirectory) {
  const Domain d = Domain::from_extent({0, 0}, {10, 10}, {5, 5});
  const auto h = ramp_field(d, 1, 1, 0);
  const fs::path file = write_height(h, "rel.exr");
  const fs::path old = fs::current_path();
  fs::current_path(policy_.output_dir);
  HeightfieldPtr back;
  EXPECT_NO_THROW(back = read_height("rel.exr", d));
  fs::current_path(old);
  ASSERT_TRUE(back);
  EXPECT_EQ(back->data, h->data);
}

TEST_F(IoTest, FailureMidWriteLeavesThePreviousFileIntact) {
  const Domain d = Domain::from_extent({0, 0}, {100, 100}, {64, 64});
  const fs::path file = write_height(ramp_field(d, 1, 0, 0), "keep.png");
  const std::string before = read_bytes(file);

  // 1. Cancelled half way through the rows, after the temporary file was created.
  CancelToken cancel;
  bool temporary_seen = false;
  auto on_progress = [&](double f) {
    if (f >= 0.5 && !cancel.cancelled()) {
      temporary_seen = !temporaries_in(dir_).empty();
      cancel.cancel();
    }
  };
  EXPECT_THROW(run_writer("WriteHeightfield", {{"path", std::string("keep.png")}}, {{"in", varied_field(d)}}, policy_,
                          on_progress, &cancel),
               Cancelled);
  EXPECT_TRUE(temporary_seen);
  EXPECT_EQ(read_bytes(file), before);
  EXPECT_TRUE(temporaries_in(dir_).empty());

  // 2. Invalid data found inside the writer (a NaN in the last row, met after the others were written).
  auto bad = std::make_shared<Heightfield>(*varied_field(d));
  bad->at(10, 0) = std::nanf("");
  for (const std::string name : {"keep.png", "keep.raw"}) {
    if (name == "keep.raw") write_height(ramp_field(d, 1, 0, 0), name);
    const std::string old = read_bytes(policy_.output_dir / name);
    try {
      run_writer("WriteHeightfield",
                 {{"path", name}, {"range", std::string("fixed")}, {"height_min", -500.0}, {"height_max", 500.0}},
                 {{"in", HeightfieldPtr(bad)}}, policy_);
      FAIL() << "no error for a NaN height in " << name;
    } catch (const NodeError& e) {
      EXPECT_NE(std::string(e.what()).find("not a finite number"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find((policy_.output_dir / name).string()), std::string::npos) << e.what();
      EXPECT_EQ(std::string(e.what()).find(".tmp-"), std::string::npos) << e.what();
    }
    EXPECT_EQ(read_bytes(policy_.output_dir / name), old) << name;
    EXPECT_TRUE(temporaries_in(dir_).empty()) << name;
  }
}

TEST_F(IoTest, OutputPathRule) {
  const Domain d = Domain::from_extent({0, 0}, {10, 10}, {4, 4});
  const auto h = ramp_field(d, 1, 0, 0);
  const std::map<std::string, PortValue> in{{"in", h}};
  const fs::path outside = dir_ / "outside.exr";
  // Absolute and climbing paths are refused under the default policy, through run_node as well.
  EXPECT_THROW(run_node("WriteHeightfield", d, {{"path", outside.string()}}, in, policy_), NodeError);
  EXPECT_THROW(run_node("WriteHeightfield", d, {{"path", std::string("../outside.exr")}}, in, policy_), NodeError);
  EXPECT_THROW(run_node("WriteHeightfield", d, {{"path", std::string("a/../../outside.exr")}}, in, policy_), NodeError);
  EXPECT_FALSE(fs::exists(outside));
  // Inside is fine, and relative paths land in the output directory.
  run_node("WriteHeightfield", d, {{"path", std::string("a/b.exr")}}, in, policy_);
  EXPECT_TRUE(fs::exists(policy_.output_dir / "a/b.exr"));
  // Allowed explicitly.
  OutputPolicy any = policy_;
  any.allow_any_path = true;
  run_node("WriteHeightfield", d, {{"path", std::string("../outside.exr")}}, in, any);
  EXPECT_TRUE(fs::exists(outside));
  fs::remove(outside);
  run_node("WriteHeightfield", d, {{"path", outside.string()}}, in, any);
  EXPECT_TRUE(fs::exists(outside));
}

TEST_F(IoTest, UncreatableDirectoryIsANodeError) {
  const Domain d = Domain::from_extent({0, 0}, {10, 10}, {4, 4});
  fs::create_directories(policy_.output_dir);
  std::ofstream(policy_.output_dir / "blocked") << "a file where a directory is needed";
  try {
    run_node("WriteHeightfield", d, {{"path", std::string("blocked/h.exr")}}, {{"in", ramp_field(d, 1, 0, 0)}},
             policy_);
    FAIL() << "no error";
  } catch (const NodeError& e) {
    EXPECT_NE(std::string(e.what()).find("blocked"), std::string::npos) << e.what();
  }
}

TEST_F(IoTest, WriterParameterErrors) {
  const Domain d = Domain::from_extent({0, 0}, {10, 10}, {4, 4});
  const std::map<std::string, PortValue> in{{"in", ramp_field(d, 1, 0, 0)}};
  EXPECT_THROW(
      run_node("WriteHeightfield", d, {{"path", std::string("h.exr")}, {"format", std::string("png16")}}, in, policy_),
      NodeError);
  EXPECT_THROW(
      run_node(
          "WriteHeightfield", d,
          {{"path", std::string("h.png")}, {"range", std::string("fixed")}, {"height_min", 5.0}, {"height_max", 5.0}},
          in, policy_),
      NodeError);
  EXPECT_NO_THROW(
      run_node("WriteHeightfield", d, {{"path", std::string("h.png")}, {"format", std::string("png16")}}, in, policy_));
  // A flat field in auto range writes code 0 and reads back exactly.
  const auto flat = std::make_shared<Heightfield>(d, 12.5f);
  const fs::path file = write_height(flat, "flat.png");
  const auto back = read_height(file, d);
  for (float v : back->data) EXPECT_EQ(v, 12.5f);
}

TEST_F(IoTest, QuantisationIsRoundToNearest) {
  const HeightRange r{-10.0, 10.0};
  EXPECT_EQ(quantize16(-10.0, r), 0);
  EXPECT_EQ(quantize16(10.0, r), 65535);
  EXPECT_EQ(quantize16(-11.0, r), 0);
  EXPECT_EQ(quantize16(1e9, r), 65535);
  EXPECT_EQ(quantize16(0.0, r), 32768);  // 32767.5 rounds up
  for (int q : {0, 1, 12345, 65534, 65535}) EXPECT_EQ(quantize16(dequantize16(static_cast<std::uint16_t>(q), r), r), q);
}

// --- WriteImage ---

ImagePtr test_image(const Domain& d, int channels) {
  auto img = std::make_shared<Image>(d, channels);
  for (int j = 0; j < d.height(); ++j)
    for (int i = 0; i < d.width(); ++i)
      for (int c = 0; c < channels; ++c)
        img->pixel(i, j)[c] = static_cast<float>(std::fmod(0.013 * i + 0.071 * j + 0.29 * c, 1.0));
  img->pixel(0, 0)[0] = -0.5f;                    // clamped to 0
  img->pixel(1, 0)[0] = 1.5f;                     // clamped to 1
  if (channels == 4) img->pixel(2, 0)[3] = 0.0f;  // transparent: its colour is still stored (straight alpha)
  return img;
}

// Pixels of a file as read by OpenImageIO in the file's own integer type, file row 0 first.
template <class T>
std::vector<T> read_pixels(const fs::path& file, OIIO::TypeDesc type, int& w, int& h, int& n) {
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);  // the file's straight alpha as stored, not premultiplied
  auto in = OIIO::ImageInput::open(file.string(), &config);
  EXPECT_TRUE(in) << OIIO::geterror();
  if (!in) return {};
  const auto& spec = in->spec();
  EXPECT_EQ(spec.format, type);
  w = spec.width;
  h = spec.height;
  n = spec.nchannels;
  std::vector<T> px(static_cast<std::size_t>(w * h * n));
  EXPECT_TRUE(in->read_image(0, 0, 0, n, type, px.data()));
  return px;
}

std::vector<float> read_pixels_float(const fs::path& file, int& w, int& h, int& n) {
  return read_pixels<float>(file, OIIO::TypeDesc::FLOAT, w, h, n);
}
std::vector<std::uint8_t> read_pixels_u8(const fs::path& file, int& w, int& h, int& n) {
  return read_pixels<std::uint8_t>(file, OIIO::TypeDesc::UINT8, w, h, n);
}

TEST(ImageFile, SrgbTransferCurve) {
  EXPECT_DOUBLE_EQ(linear_to_srgb(0.0), 0.0);
  EXPECT_DOUBLE_EQ(linear_to_srgb(1.0), 1.0);
  EXPECT_NEAR(linear_to_srgb(0.5), 0.735357, 1e-6);
  EXPECT_NEAR(linear_to_srgb(0.001), 0.01292, 1e-9);  // linear toe
  for (double v = 0; v <= 1.0; v += 0.01) EXPECT_NEAR(srgb_to_linear(linear_to_srgb(v)), v, 1e-12);
}

// A 16-bit file written with range 'auto' keeps its metres beside it: the sidecar's mapping turns the stored
// integers back into heights within half a step, and gives Unreal's landscape scale.
TEST_F(IoTest, SixteenBitHeightsCarryTheirMappingInASidecar) {
  const Domain d = Domain::from_extent({1000, 2000}, {640, 640}, {65, 65});  // 10 m cells, square for RAW
  auto h = std::make_shared<Heightfield>(d);
  for (int j = 0; j < d.height(); ++j)
    for (int i = 0; i < d.width(); ++i) h->at(i, j) = static_cast<float>(-120.0 + 3.5 * i + 7.25 * j);
  for (const std::string name : {"h.png", "h.raw"}) {
    SCOPED_TRACE(name);
    const fs::path image = write_height(h, name);
    const auto side = nlohmann::json::parse(test::read_text(fs::path(image.string() + ".json")));
    EXPECT_EQ(side["image"], name);
    EXPECT_EQ(side["samples"], nlohmann::json({65, 65}));
    EXPECT_DOUBLE_EQ(side["cell_size"][0].get<double>(), 10.0);
    EXPECT_DOUBLE_EQ(side["south_west_sample"][1].get<double>(), 2000.0);
    const double lo = side["height_at_0"], hi = side["height_at_65535"];
    EXPECT_NEAR(lo, -120.0, 1e-4);
    EXPECT_NEAR(hi, -120.0 + 3.5 * 64 + 7.25 * 64, 1e-3);
    EXPECT_DOUBLE_EQ(side["unreal"]["scale_x"].get<double>(), 1000.0);
    EXPECT_NEAR(side["unreal"]["scale_z"].get<double>(), (hi - lo) / 512.0 * 100.0, 1e-9);
    // The stored integers, read raw (north row first), through the sidecar's mapping.
    const std::string bytes = test::read_text(image);
    if (name == "h.raw") {
      ASSERT_EQ(bytes.size(), 65u * 65u * 2u);
      for (int r = 0; r < 65; ++r)
        for (int i = 0; i < 65; ++i) {
          const auto k = static_cast<std::size_t>((r * 65 + i) * 2);
          const int v = static_cast<unsigned char>(bytes[k]) | static_cast<unsigned char>(bytes[k + 1]) << 8;
          EXPECT_NEAR(lo + v / 65535.0 * (hi - lo), h->at(i, 64 - r), (hi - lo) / 65535.0);
        }
    }
  }
}

// Weights, masks and ids are data: stored as their values whatever `srgb` says (splat weights sum to 255).
TEST_F(IoTest, WriteImagePng8StoresDataImagesLinear) {
  const Domain d = Domain::from_extent({0, 0}, {10, 10}, {23, 11});
  const auto img = test_image(d, 4);
  ASSERT_FALSE(img->color);
  const auto files = run_writer("WriteImage", {{"path", std::string("img/weights.png")}}, {{"in", img}}, policy_);
  ASSERT_EQ(files.size(), 1u);
  int w = 0, h = 0, n = 0;
  const auto px = read_pixels<std::uint8_t>(files[0], OIIO::TypeDesc::UINT8, w, h, n);
  ASSERT_EQ(n, 4);
  for (int r = 0; r < h; ++r)
    for (int i = 0; i < w; ++i)
      for (int c = 0; c < 4; ++c) {
        const double v = std::clamp(img->pixel(i, h - 1 - r)[c], 0.0f, 1.0f);
        ASSERT_EQ(px[static_cast<std::size_t>((r * w + i) * 4 + c)], std::lround(v * 255)) << i << "," << r;
      }
}

TEST_F(IoTest, WriteImagePng8EncodesSrgbAndKeepsAlphaLinear) {
  const Domain d = Domain::from_extent({0, 0}, {10, 10}, {23, 11});
  auto color = std::make_shared<Image>(*test_image(d, 4));
  color->color = true;
  const ImagePtr img = color;
  const auto files = run_writer("WriteImage", {{"path", std::string("img/colour.png")}}, {{"in", img}}, policy_);
  ASSERT_EQ(files.size(), 1u);
  int w = 0, h = 0, n = 0;
  const auto px = read_pixels<std::uint8_t>(files[0], OIIO::TypeDesc::UINT8, w, h, n);
  ASSERT_EQ(w, 23);
  ASSERT_EQ(h, 11);
  ASSERT_EQ(n, 4);
  for (int r = 0; r < h; ++r)
    for (int i = 0; i < w; ++i)
      for (int c = 0; c < 4; ++c) {
        const double v = std::clamp(img->pixel(i, h - 1 - r)[c], 0.0f, 1.0f);  // north row first
        const double stored = c == 3 ? v : linear_to_srgb(v);
        ASSERT_EQ(px[static_cast<std::size_t>((r * w + i) * 4 + c)], std::lround(stored * 255))
            << i << "," << r << "," << c;
      }
}

TEST_F(IoTest, WriteImagePng16Linear) {
  const Domain d = Domain::from_extent({0, 0}, {10, 10}, {9, 7});
  const auto img = test_image(d, 1);
  const auto files =
      run_writer("WriteImage", {{"path", std::string("grey.png")}, {"bit_depth", std::string("16")}, {"srgb", false}},
                 {{"in", img}}, policy_);
  int w = 0, h = 0, n = 0;
  const auto px = read_pixels<std::uint16_t>(files.at(0), OIIO::TypeDesc::UINT16, w, h, n);
  ASSERT_EQ(n, 1);
  for (int r = 0; r < h; ++r)
    for (int i = 0; i < w; ++i)
      ASSERT_EQ(px[static_cast<std::size_t>(r * w + i)],
                std::lround(std::clamp(img->pixel(i, h - 1 - r)[0], 0.0f, 1.0f) * 65535.0));
}

TEST_F(IoTest, WriteImageFloatFormatsAreExact) {
  const Domain d = Domain::from_extent({0, 0}, {10, 10}, {13, 6});
  auto img = std::make_shared<Image>(*test_image(d, 5));
  img->channel_names = {"grass", "rock", "sand", "snow", "water"};
  for (const std::string name : {"weights.exr", "weights.tif"}) {
    const auto files = run_writer("WriteImage", {{"path", name}}, {{"in", ImagePtr(img)}}, policy_);
    int w = 0, h = 0, n = 0;
    const auto px = read_pixels<float>(files.at(0), OIIO::TypeDesc::FLOAT, w, h, n);
    ASSERT_EQ(n, 5);
    for (int r = 0; r < h; ++r)
      for (int i = 0; i < w; ++i)
        for (int c = 0; c < n; ++c)
          ASSERT_EQ(px[static_cast<std::size_t>((r * w + i) * n + c)], img->pixel(i, h - 1 - r)[c]) << name;
    if (name == "weights.exr") {
      auto in = OIIO::ImageInput::open(files[0].string());
      ASSERT_TRUE(in);
      std::vector<std::string> names(in->spec().channelnames.begin(), in->spec().channelnames.end());
      std::sort(names.begin(), names.end());  // EXR stores channels sorted by name
      EXPECT_EQ(names, img->channel_names);
    }
  }
  // PNG cannot hold 5 channels: a clear error, no file.
  EXPECT_THROW(run_writer("WriteImage", {{"path", std::string("weights.png")}}, {{"in", ImagePtr(img)}}, policy_),
               NodeError);
  EXPECT_FALSE(fs::exists(policy_.output_dir / "weights.png"));
  EXPECT_TRUE(temporaries_in(dir_).empty());
}

// --- WritePoints ---

PointsPtr test_points() {
  auto p = std::make_shared<Points>();
  for (int k = 0; k < 37; ++k) {
    const auto idx = p->add({k * 1.5f, -k * 0.25f, 100.0f + k / 3.0f}, k % 4);
    p->rotation[idx] = glm::normalize(glm::quat(1.0f, 0.1f * k, 0.0f, -0.2f));
    p->scale[idx] = {1.0f + k / 7.0f, 1.0f, 0.5f};
  }
  auto& age = p->attribute("zeta_age");
  auto& density = p->attribute("density");
  for (std::size_t k = 0; k < p->size(); ++k) {
    age[k] = static_cast<float>(k) / 9.0f;
    density[k] = 1e-7f * static_cast<float>(k);
  }
  return p;
}

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::stringstream in(s);
  for (std::string item; std::getline(in, item, sep);) out.push_back(item);
  return out;
}

void expect_row(const std::vector<std::string>& fields, const Points& p, std::size_t k) {
  ASSERT_EQ(fields.size(), 13u);
  const auto& q = p.rotation[k];
  const float expected[] = {p.position[k].x, p.position[k].y, p.position[k].z, q.w, q.x, q.y, q.z,
                            p.scale[k].x,    p.scale[k].y,    p.scale[k].z};
  for (int c = 0; c < 10; ++c) EXPECT_EQ(std::stof(fields[static_cast<std::size_t>(c)]), expected[c]) << k << "," << c;
  EXPECT_EQ(std::stoi(fields[10]), p.class_id[k]);
  EXPECT_EQ(std::stof(fields[11]), p.attributes.at("density")[k]);  // attributes sorted by name
  EXPECT_EQ(std::stof(fields[12]), p.attributes.at("zeta_age")[k]);
}

TEST_F(IoTest, WritePointsCsv) {
  const auto p = test_points();
  const auto files = run_writer("WritePoints", {{"path", std::string("pts/trees.csv")}}, {{"in", p}}, policy_);
  const auto lines = split(read_bytes(files.at(0)), '\n');
  ASSERT_EQ(lines.size(), p->size() + 1);
  EXPECT_EQ(lines[0], "x,y,z,qw,qx,qy,qz,sx,sy,sz,class,density,zeta_age");
  for (std::size_t k = 0; k < p->size(); ++k) expect_row(split(lines[k + 1], ','), *p, k);
}

TEST_F(IoTest, WritePointsPly) {
  const auto p = test_points();
  const auto files = run_writer("WritePoints", {{"path", std::string("trees.ply")}}, {{"in", p}}, policy_);
  const auto lines = split(read_bytes(files.at(0)), '\n');
  const auto end = std::find(lines.begin(), lines.end(), "end_header");
  ASSERT_NE(end, lines.end());
  const std::vector<std::string> header(lines.begin(), end);
  EXPECT_EQ(header[0], "ply");
  EXPECT_EQ(header[1], "format ascii 1.0");
  EXPECT_NE(std::find(header.begin(), header.end(), "element vertex 37"), header.end());
  std::vector<std::string> props;
  for (const auto& l : header)
    if (l.rfind("property ", 0) == 0) props.push_back(l);
  ASSERT_EQ(props.size(), 13u);
  EXPECT_EQ(props[0], "property float x");
  EXPECT_EQ(props[10], "property int class");
  EXPECT_EQ(props[11], "property float density");
  EXPECT_EQ(props[12], "property float zeta_age");
  ASSERT_EQ(static_cast<std::size_t>(lines.end() - end - 1), p->size());
  for (std::size_t k = 0; k < p->size(); ++k)
    expect_row(split(*(end + 1 + static_cast<std::ptrdiff_t>(k)), ' '), *p, k);
}

TEST_F(IoTest, WritePointsAttributeNames) {
  auto p = std::make_shared<Points>(*test_points());
  p->attribute("height, m");
  const auto csv = run_writer("WritePoints", {{"path", std::string("q.csv")}}, {{"in", PointsPtr(p)}}, policy_);
  EXPECT_EQ(split(read_bytes(csv.at(0)), '\n')[0], "x,y,z,qw,qx,qy,qz,sx,sy,sz,class,density,\"height, m\",zeta_age");
  EXPECT_THROW(run_writer("WritePoints", {{"path", std::string("q.ply")}}, {{"in", PointsPtr(p)}}, policy_), NodeError);
  auto clash = std::make_shared<Points>(*test_points());
  clash->attribute("x");
  EXPECT_THROW(run_writer("WritePoints", {{"path", std::string("c.csv")}}, {{"in", PointsPtr(clash)}}, policy_),
               NodeError);
  EXPECT_TRUE(temporaries_in(dir_).empty());
  EXPECT_FALSE(fs::exists(policy_.output_dir / "q.ply"));
}

TEST_F(IoTest, WritePointsEmpty) {
  const auto files = run_writer("WritePoints", {{"path", std::string("none.csv")}},
                                {{"in", std::make_shared<const Points>()}}, policy_);
  EXPECT_EQ(read_bytes(files.at(0)), "x,y,z,qw,qx,qy,qz,sx,sy,sz,class\n");
}

}  // namespace
}  // namespace orogen
