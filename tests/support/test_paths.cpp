#include "support/test_paths.h"

#include <atomic>

#include <unistd.h>

namespace orogen::test {

std::filesystem::path source_dir() { return OROGEN_SOURCE_DIR; }
std::filesystem::path cli_binary() { return OROGEN_CLI; }

std::filesystem::path scratch_dir(const std::string& name) {
  static std::atomic<int> counter{0};
  const auto dir = std::filesystem::path(OROGEN_BINARY_DIR) / "test-scratch" /
                   (name + "-" + std::to_string(::getpid()) + "-" + std::to_string(counter.fetch_add(1)));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace orogen::test
