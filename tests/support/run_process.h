#pragma once
// Runs a command line for end-to-end tests and captures its exit code, standard output and error.
#include <filesystem>
#include <string>
#include <vector>

namespace orogen::test {

struct ProcessResult {
  int exit_code = -1;
  std::string out, err;
};

// Runs `program` with `args` (no shell; arguments passed verbatim), with an optional working directory.
ProcessResult run_process(const std::filesystem::path& program, const std::vector<std::string>& args,
                          const std::filesystem::path& working_dir = {});

std::string read_text(const std::filesystem::path& p);
void write_text(const std::filesystem::path& p, const std::string& text);

}  // namespace orogen::test
