#pragma once
// What the end-to-end tests of distributed builds share (tests/test_distributed*.cpp): launching orogen on MPI ranks,
// the tiles' file names and windows, and the tiles' rasters put together on the whole domain.
#include <filesystem>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

#include "support/run_process.h"
#include "support/tile_windows.h"  // edge, tiles_text

namespace orogen::test {

// Open MPI refuses root without these, and more ranks than cores; MPICH ignores them.
void allow_launcher();

// `mpiexec -n ranks orogen args...` (the test program's OROGEN_MPIEXEC: only those programs know the launcher).
ProcessResult mpirun(const std::string& mpiexec, int ranks, const std::vector<std::string>& args);

std::string file_bytes(const std::filesystem::path& p);

// The file tile i,j writes for the untiled build's `rel` under `dir`: "<stem>_xI_yJ<ext>".
std::filesystem::path tile_file(const std::filesystem::path& dir, const std::filesystem::path& rel, int i, int j);

// A whole raster, south row first: at(i, j) with j growing northwards (+y).
struct FloatRaster {
  int width = 0, height = 0;
  std::vector<float> values;
  float at(int i, int j) const { return values[static_cast<std::size_t>(j) * width + i]; }
  float& at(int i, int j) { return values[static_cast<std::size_t>(j) * width + i]; }
};

// Channel `channel` of a raster file.
FloatRaster read_float_raster(const std::filesystem::path& file, int channel = 0);

// The tiles of the untiled build's `rel` under `dir` (tile_file) put together into one raster of `size` samples. A
// tile whose window is not the tiling's fails the test and leaves its samples NaN.
FloatRaster stitch(const std::filesystem::path& dir, const std::filesystem::path& rel, glm::ivec2 counts,
                   glm::ivec2 size, int channel = 0);

bool same_bits(const FloatRaster& a, const FloatRaster& b);

}  // namespace orogen::test
