#include "support/distributed_builds.h"

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>

#include <gtest/gtest.h>

#include "nodes/io/heightfield_file.h"
#include "support/test_paths.h"

namespace orogen::test {

namespace fs = std::filesystem;

void allow_launcher() {
  ::setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1);
  ::setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
  ::setenv("OMPI_MCA_rmaps_base_oversubscribe", "1", 1);
}

ProcessResult mpirun(const std::string& mpiexec, int ranks, const std::vector<std::string>& args) {
  allow_launcher();
  std::vector<std::string> all = {"-n", std::to_string(ranks), cli_binary().string()};
  all.insert(all.end(), args.begin(), args.end());
  return run_process(mpiexec, all);
}

std::string file_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

fs::path tile_file(const fs::path& dir, const fs::path& rel, int i, int j) {
  return dir / rel.parent_path() /
         (rel.stem().string() + "_x" + std::to_string(i) + "_y" + std::to_string(j) + rel.extension().string());
}

FloatRaster read_float_raster(const fs::path& file, int channel) {
  const auto raw = read_height_raster(file, channel);
  FloatRaster r{raw.width, raw.height, std::vector<float>(raw.values.size())};
  for (int j = 0; j < r.height; ++j)  // files store the northern row first
    for (int i = 0; i < r.width; ++i)
      r.at(i, j) = static_cast<float>(raw.values[static_cast<std::size_t>(r.height - 1 - j) * r.width + i]);
  return r;
}

FloatRaster stitch(const fs::path& dir, const fs::path& rel, glm::ivec2 counts, glm::ivec2 size, int channel) {
  FloatRaster whole{size.x, size.y, std::vector<float>(static_cast<std::size_t>(size.x) * size.y, NAN)};
  for (int tj = 0; tj < counts.y; ++tj)
    for (int ti = 0; ti < counts.x; ++ti) {
      const FloatRaster t = read_float_raster(tile_file(dir, rel, ti, tj), channel);
      const int i0 = edge(ti, size.x, counts.x), j0 = edge(tj, size.y, counts.y);
      const bool window =
          t.width == edge(ti + 1, size.x, counts.x) - i0 + 1 && t.height == edge(tj + 1, size.y, counts.y) - j0 + 1;
      EXPECT_TRUE(window) << tile_file(dir, rel, ti, tj) << ": " << t.width << "x" << t.height
                          << " samples, not the tiling's window";
      if (!window) continue;
      for (int j = 0; j < t.height; ++j)
        for (int i = 0; i < t.width; ++i) whole.at(i0 + i, j0 + j) = t.at(i, j);
    }
  return whole;
}

bool same_bits(const FloatRaster& a, const FloatRaster& b) {
  return a.width == b.width && a.height == b.height &&
         std::memcmp(a.values.data(), b.values.data(), a.values.size() * sizeof(float)) == 0;
}

}  // namespace orogen::test
