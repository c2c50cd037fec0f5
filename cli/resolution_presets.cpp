#include "cli/resolution_presets.h"

namespace orogen::cli {

const std::vector<ResolutionPreset>& resolution_presets() {
  static const std::vector<ResolutionPreset> presets = {
      {"unreal-505", 505}, {"unreal-1009", 1009}, {"unreal-2017", 2017}, {"unreal-4033", 4033}, {"unreal-8129", 8129},
      {"unity-513", 513},  {"unity-1025", 1025},  {"unity-2049", 2049},  {"unity-4097", 4097},
  };
  return presets;
}

std::optional<int> resolution_preset(const std::string& name) {
  for (const auto& p : resolution_presets())
    if (name == p.name) return p.samples;
  return std::nullopt;
}

std::string resolution_preset_names() {
  std::string names;
  for (const auto& p : resolution_presets()) names += (names.empty() ? "" : ", ") + std::string(p.name);
  return names;
}

}  // namespace orogen::cli
