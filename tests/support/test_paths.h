#pragma once
// Locations tests need: the source tree (example graphs), the build tree (the orogen binary), and fresh
// scratch directories.
#include <filesystem>
#include <string>

namespace orogen::test {

std::filesystem::path source_dir();
std::filesystem::path cli_binary();
// A new empty directory under the build tree, unique per call; `name` makes it recognisable.
std::filesystem::path scratch_dir(const std::string& name);

}  // namespace orogen::test
