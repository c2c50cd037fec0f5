// The main of the sanitizer build's one test program (tests/CMakeLists.txt), which links every tests/test_*.cpp:
// `orogen_tests --test-file=test_<area>.cpp` runs the tests that file defines and no other, so ctest still runs
// each file's tests in a process of their own, as the Release build's programs do. Without --test-file it runs
// what gtest's own flags select (every test by default).
#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <string_view>

namespace {

constexpr std::string_view kTestFileFlag = "--test-file=";

bool is_from_file(const char* path, std::string_view file) {
  const std::string_view p = path ? path : "";
  return p == file || (p.size() > file.size() && p.ends_with(file) && p[p.size() - file.size() - 1] == '/');
}

// gtest's filter naming exactly the tests whose source file is `file` (empty if it defines none).
std::string filter_for_file(std::string_view file) {
  std::string filter;
  const auto& unit = *testing::UnitTest::GetInstance();
  for (int s = 0; s < unit.total_test_suite_count(); ++s) {
    const auto& suite = *unit.GetTestSuite(s);
    for (int t = 0; t < suite.total_test_count(); ++t) {
      const auto& info = *suite.GetTestInfo(t);
      if (!is_from_file(info.file(), file)) continue;
      if (!filter.empty()) filter += ':';
      filter += std::string(suite.name()) + "." + info.name();
    }
  }
  return filter;
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  std::string file;
  for (int i = 1; i < argc; ++i) {
    const std::string_view arg = argv[i];
    if (arg.starts_with(kTestFileFlag)) {
      file = arg.substr(kTestFileFlag.size());
    } else {
      std::fprintf(stderr, "unknown argument '%s' (expected --test-file=test_<area>.cpp or gtest's flags)\n", argv[i]);
      return 2;
    }
  }
  if (!file.empty()) {
    if (GTEST_FLAG_GET(filter) != "*") {
      std::fprintf(stderr, "--test-file and --gtest_filter cannot be combined\n");
      return 2;
    }
    const std::string filter = filter_for_file(file);
    if (filter.empty()) {
      std::fprintf(stderr, "no test is defined in '%s'\n", file.c_str());
      return 2;
    }
    GTEST_FLAG_SET(filter, filter);
  }
  return RUN_ALL_TESTS();
}
