// Faults in distributed builds (issue 24, docs/distributed.md): Ctrl+C in the middle of a simulation that runs across
// the ranks' tiles stops every rank in the same round with nothing partial written, and a rank killed in the middle
// of one fails the job with the launcher's message naming the rank, after which a re-run with the same --cache-dir
// takes the nodes finished before from the cache. The storm below would run for hours: only a stop ends it. Skipped,
// with a message, when orogen was built without MPI (OROGEN_MPI off).
#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "support/distributed_builds.h"
#include "support/run_process.h"
#include "support/test_paths.h"

namespace orogen::test {
namespace {

namespace fs = std::filesystem;

const std::string kMpiexec = OROGEN_MPIEXEC;  // empty: built without MPI

// A fill across the tiles, then a storm of a million simulated seconds across them (tens of thousands of rounds).
const char* kStormGraph = R"({
  "format": "orogen-graph", "version": 7,
  "domain": { "size": [4096, 4096], "resolution": [65, 65] },
  "nodes": [
    { "id": "fbm", "type": "FBM", "params": { "feature_size": 1200, "amplitude": 400, "octaves": 6, "seed": 7 } },
    { "id": "filled", "type": "FillDepressions", "inputs": { "in": "fbm.out" } },
    { "id": "storm", "type": "PipeErosion", "inputs": { "in": "filled.out" },
      "params": { "duration": 1000000, "rainfall_rate": 200, "evaporation": 0.002, "seed": 9 } },
    { "id": "save", "type": "WriteHeightfield", "inputs": { "in": "storm.out" }, "params": { "path": "height.tif" } }
  ]
})";

// `mpiexec -n 2 orogen eval ... --tiles 2x1` in the background, its standard error into a file.
struct Launched {
  pid_t pid = -1;
  fs::path err;
};

Launched launch(const fs::path& dir, const std::vector<std::string>& extra) {
  allow_launcher();
  write_text(dir / "g.json", kStormGraph);
  std::vector<std::string> args = {
      kMpiexec,  "-n", "2", cli_binary().string(), "eval", (dir / "g.json").string(), "-o", (dir / "out").string(),
      "--tiles", "2x1"};
  args.insert(args.end(), extra.begin(), extra.end());
  Launched l{-1, dir / "err.txt"};
  l.pid = ::fork();
  if (l.pid == 0) {
    const int out = ::open("/dev/null", O_WRONLY), err = ::open(l.err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ::dup2(out, 1);
    ::dup2(err, 2);
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  return l;
}

// Waits until the job's standard error holds `text`; false after `seconds` (the job is then killed).
bool wait_for_text(const Launched& l, const std::string& text, int seconds) {
  for (int i = 0; i < seconds * 20; ++i) {
    if (read_text(l.err).find(text) != std::string::npos) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return false;
}

// The job's exit status once it ends; -1 if it is still running after `seconds` (a hang: it is then killed).
int wait_for_end(const Launched& l, int seconds) {
  for (int i = 0; i < seconds * 20; ++i) {
    int status = 0;
    if (::waitpid(l.pid, &status, WNOHANG) == l.pid) return status;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  ::kill(l.pid, SIGKILL);
  ::waitpid(l.pid, nullptr, 0);
  return -1;
}

// The ranks: the launcher's children (Open MPI starts local ranks itself).
std::vector<pid_t> ranks_of(pid_t launcher) {
  std::vector<pid_t> ranks;
  for (const auto& e : fs::directory_iterator("/proc")) {
    const std::string name = e.path().filename().string();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    const std::string stat = read_text(e.path() / "stat");
    // pid (comm) state ppid ...: the command may hold spaces, so read after its closing parenthesis.
    const auto close = stat.rfind(')');
    if (close == std::string::npos) continue;
    int ppid = 0;
    char state = 0;
    if (std::sscanf(stat.c_str() + close + 1, " %c %d", &state, &ppid) == 2 && ppid == launcher)
      ranks.push_back(static_cast<pid_t>(std::stoi(name)));
  }
  return ranks;
}

TEST(DistributedFaults, CtrlCStopsEveryRankInTheSameRoundOfASimulation) {
  if (kMpiexec.empty()) GTEST_SKIP() << "orogen was built without MPI (OROGEN_MPI off)";
  const fs::path dir = scratch_dir("distributed-ctrl-c");
  const Launched job = launch(dir, {});
  // The fill before the storm has run across the tiles: the storm's rounds come next.
  ASSERT_TRUE(wait_for_text(job, "node 'filled' (FillDepressions) computed across the tiles", 120))
      << read_text(job.err);
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  ::kill(job.pid, SIGINT);  // a terminal's Ctrl+C reaches the launcher, which passes it to the ranks
  const int status = wait_for_end(job, 60);
  const std::string err = read_text(job.err);
  ASSERT_NE(status, -1) << "the job did not stop:\n" << err;
  EXPECT_FALSE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << err;
  // Both ranks stop between the same two rounds of the storm.
  const std::string stop = "interrupted in node 'storm' (PipeErosion) across the tiles, at round ";
  const auto first = err.find(stop);
  ASSERT_NE(first, std::string::npos) << err;
  const auto second = err.find(stop, first + 1);
  ASSERT_NE(second, std::string::npos) << "one rank only:\n" << err;
  EXPECT_EQ(std::stol(err.substr(first + stop.size())), std::stol(err.substr(second + stop.size()))) << err;
  EXPECT_FALSE(fs::exists(dir / "out" / "height_x0_y0.tif"));
}

TEST(DistributedFaults, ARankKilledInASimulationFailsTheJobAndTheRerunTakesTheFinishedNodesFromTheCache) {
  if (kMpiexec.empty()) GTEST_SKIP() << "orogen was built without MPI (OROGEN_MPI off)";
  const fs::path dir = scratch_dir("distributed-killed-rank");
  const std::vector<std::string> cache = {"--cache-dir", (dir / "cache").string()};
  const Launched job = launch(dir, cache);
  ASSERT_TRUE(wait_for_text(job, "node 'filled' (FillDepressions) computed across the tiles", 120))
      << read_text(job.err);
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  const std::vector<pid_t> ranks = ranks_of(job.pid);
  ASSERT_EQ(ranks.size(), 2u);
  ::kill(ranks.back(), SIGKILL);
  const int status = wait_for_end(job, 60);
  const std::string err = read_text(job.err);
  ASSERT_NE(status, -1) << "the job did not stop:\n" << err;
  EXPECT_FALSE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << err;
  // The launcher names the rank and the signal (Open MPI: "process rank 1 ... exited on signal 9 (Killed)").
  EXPECT_NE(err.find("signal 9"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(dir / "out" / "height_x0_y0.tif"));
  // A shorter storm this time: the fill finished before the kill comes from the cache on both tiles.
  auto rerun = mpirun(kMpiexec, 2,
                      {"eval", (dir / "g.json").string(), "-o", (dir / "out").string(), "--tiles", "2x1", "--set",
                       "storm.duration=60", cache[0], cache[1]});
  ASSERT_EQ(rerun.exit_code, 0) << rerun.err;
  EXPECT_NE(rerun.err.find("node 'filled' (FillDepressions) cached on every tile"), std::string::npos) << rerun.err;
  EXPECT_NE(rerun.err.find("node 'storm' (PipeErosion) computed across the tiles"), std::string::npos) << rerun.err;
  EXPECT_TRUE(fs::exists(dir / "out" / "height_x1_y0.tif"));
}

}  // namespace
}  // namespace orogen::test
