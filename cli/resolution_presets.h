#pragma once
// Sample counts game engines import heightmaps at, by name, for --resolution: Unreal Engine's recommended
// landscape sizes (sections of 63..255 quads: 505, 1009, 2017, 4033, 8129 samples a side) and Unity's terrain
// heightmap resolutions (2^n + 1). A name gives the sample count along x; y follows the domain's aspect.
#include <optional>
#include <string>
#include <vector>

namespace orogen::cli {

struct ResolutionPreset {
  const char* name;
  int samples;
};

const std::vector<ResolutionPreset>& resolution_presets();
// The sample count of a preset name ("unreal-2017", "unity-1025"), or nothing.
std::optional<int> resolution_preset(const std::string& name);
// "unreal-505, unreal-1009, ..." for messages and --help.
std::string resolution_preset_names();

}  // namespace orogen::cli
