// The five seed graphs end to end at full resolution: each is evaluated by the `orogen` command in a child
// process (no persistent cache, a fresh output directory), and the wall time, the CPU time (user + system of
// the child and its threads) and the peak memory (maximum resident set size) that wait4() reports are
// printed, one line per graph.
//
//   orogen_bench_seeds [--graphs NAME,NAME...] [--resolution NAME=N ...] [--repeat K] [--keep DIR]
//
// Full resolutions: the source paper's largest figure, or 1 to 2 m per sample where it gives none:
//   seamscape.json (Ekman et al. 2016)  2049 x 2049 (2 m over its 4096 m square; the paper gives no figure)
//   rural_resources.json (Long 2016)    1024 x 1024 (H. Long 2016 times water flow and k-means up to 1024^2)
//   voronoi_island.json (Weiss 2015)    1024 x 1024
//   game_world.json (Zaiz 2022)         1025 x 1025 (2 m over its 2048 m square; the paper gives no figure)
//   forest.json (Potter 2017)           1025 x 1025 (Unity's 1025^2 heightmap: 1 m over the 1024 m forest)
// A missing graph file is skipped with a message. With --repeat K each graph runs K times and the run with
// the least CPU time is reported (the machine may be shared: compare runs made together).
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

struct Seed {
  std::string file;
  std::string resolution;  // empty: the file's
};

struct Measure {
  int exit_code = -1;
  double wall_s = 0, cpu_s = 0;
  long max_rss_kb = 0;
};

Measure run(const std::vector<std::string>& args) {
  std::vector<char*> argv;
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  const auto t0 = std::chrono::steady_clock::now();
  const pid_t pid = fork();
  if (pid == 0) {
    execv(argv[0], argv.data());
    std::perror("execv");
    _exit(127);
  }
  Measure m;
  if (pid < 0) return m;
  int status = 0;
  rusage ru{};
  if (wait4(pid, &status, 0, &ru) < 0) return m;
  m.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  m.cpu_s = static_cast<double>(ru.ru_utime.tv_sec + ru.ru_stime.tv_sec) +
            1e-6 * static_cast<double>(ru.ru_utime.tv_usec + ru.ru_stime.tv_usec);
  m.max_rss_kb = ru.ru_maxrss;
  m.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return m;
}

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, sep))
    if (!item.empty()) out.push_back(item);
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<Seed> seeds = {{"seamscape.json", "2049"},
                             {"game_world.json", "1025"},
                             {"voronoi_island.json", "1024"},
                             {"rural_resources.json", "1024"},
                             {"forest.json", "1025"}};
  std::vector<std::string> only;
  int repeat = 1;
  fs::path keep;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool has_value = i + 1 < argc;
    if (a == "--graphs" && has_value) {
      only = split(argv[++i], ',');
    } else if (a == "--resolution" && has_value) {
      const std::string v = argv[++i];
      const auto eq = v.find('=');
      bool found = false;
      for (auto& s : seeds)
        if (eq != std::string::npos && (s.file == v.substr(0, eq) || s.file == v.substr(0, eq) + ".json")) {
          s.resolution = v.substr(eq + 1);
          found = true;
        }
      if (!found) {
        std::fprintf(stderr, "--resolution wants NAME=N with NAME one of the seed graphs, got %s\n", v.c_str());
        return 2;
      }
    } else if (a == "--repeat" && has_value) {
      repeat = std::max(1, std::atoi(argv[++i]));
    } else if (a == "--keep" && has_value) {
      keep = argv[++i];
    } else {
      std::fprintf(stderr, "usage: %s [--graphs NAME,NAME...] [--resolution NAME=N ...] [--repeat K] [--keep DIR]\n",
                   argv[0]);
      return a == "--help" || a == "-h" ? 0 : 2;
    }
  }
  const fs::path source = OROGEN_SOURCE_DIR, cli = OROGEN_CLI;
  const fs::path scratch =
      keep.empty() ? fs::temp_directory_path() / ("orogen-bench-seeds-" + std::to_string(getpid())) : keep;
  std::printf("%-22s %11s %9s %9s %12s  %s\n", "graph", "resolution", "wall s", "cpu s", "peak RSS MB", "command");
  int failures = 0;
  for (const auto& s : seeds) {
    const std::string name = fs::path(s.file).stem().string();
    if (!only.empty() && std::find(only.begin(), only.end(), name) == only.end() &&
        std::find(only.begin(), only.end(), s.file) == only.end())
      continue;
    const fs::path graph = source / "graphs" / s.file;
    if (!fs::exists(graph)) {
      std::printf("%-22s skipped: %s does not exist\n", s.file.c_str(), graph.c_str());
      continue;
    }
    Measure best;
    std::string command;
    for (int r = 0; r < repeat; ++r) {
      const fs::path out = scratch / name;
      fs::remove_all(out);
      std::vector<std::string> args = {cli.string(), "eval", graph.string(), "-o", out.string(), "--quiet"};
      if (!s.resolution.empty()) {
        args.push_back("--resolution");
        args.push_back(s.resolution);
      }
      command.clear();
      for (std::size_t k = 1; k < args.size(); ++k) command += (k > 1 ? " " : "orogen ") + args[k];
      const Measure m = run(args);
      if (m.exit_code != 0) {
        best = m;
        break;
      }
      if (r == 0 || m.cpu_s < best.cpu_s) best = m;
    }
    if (best.exit_code != 0) {
      std::printf("%-22s FAILED (exit %d)  %s\n", s.file.c_str(), best.exit_code, command.c_str());
      ++failures;
      continue;
    }
    std::printf("%-22s %11s %9.2f %9.2f %12.1f  %s\n", s.file.c_str(),
                s.resolution.empty() ? "file" : s.resolution.c_str(), best.wall_s, best.cpu_s,
                static_cast<double>(best.max_rss_kb) / 1024.0, command.c_str());
    std::fflush(stdout);
  }
  if (keep.empty()) fs::remove_all(scratch);
  return failures == 0 ? 0 : 1;
}
