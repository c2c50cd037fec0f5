#pragma once
// The island's meshes and rasters index their arrays by int cell and vertex ids: ix() is the one place an id
// turns into a container index.
#include <cstddef>

namespace orogen::island {

using Index = std::size_t;
inline Index ix(int k) { return static_cast<Index>(k); }

}  // namespace orogen::island
