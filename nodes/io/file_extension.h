#pragma once
// The one place a file's extension is read for its format: case-insensitively, so "S.GLB" is binary glTF
// like "s.glb" (every *_format_from_path uses it).
#include <filesystem>
#include <string>

namespace orogen {

// The extension of `path` with its dot, ASCII letters in lower case ("" when there is none).
inline std::string lower_extension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  for (char& c : ext)
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  return ext;
}

}  // namespace orogen
