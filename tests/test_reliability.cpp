// Issue 15: the attacks on the file system and on the values between nodes, each reproduced. Every test
// here failed on the code before the fix it names.
//
//  1 full disk          FullDisk.*                      6 numeric options    NumericOptions.*
//  2 symlink escape     SymlinkEscape.*                 7 NaN lookups        NonFinite.*
//  3 NUL in a path      ControlCharacters.*             8 degenerate domain  DegenerateDomain.*
//  4 long file name     LongFileName.*                  9 huge requests      HugeRequest.*
//  5 damaged cache      DamagedCache.*                 10 stale temporaries  StaleTemporaries.*
//  and the cache of issue 14: CacheBound.*, SharedCache.*; crashes: KillNine.*
#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <random>
#include <thread>

#include <nlohmann/json.hpp>

#include "evaluator/cache_key.h"
#include "evaluator/disk_cache.h"
#include "graph/atomic_file.h"
#include "graph/checked_file.h"
#include "graph/domain.h"
#include "graph/heightfield.h"
#include "graph/output_path.h"
#include "graph/param_value.h"
#include "graph/temporary_lock.h"
#include "nodes/field/bicubic.h"
#include "support/run_process.h"
#include "support/sanitizers.h"
#include "support/test_paths.h"

namespace orogen::test {
namespace {

namespace fs = std::filesystem;

ProcessResult orogen(const std::vector<std::string>& args) { return run_process(cli_binary(), args); }

// orogen with extra environment variables ("NAME=value"), through env(1).
ProcessResult orogen_env(const std::vector<std::string>& env, const std::vector<std::string>& args) {
  std::vector<std::string> all = env;
  all.push_back(cli_binary().string());
  all.insert(all.end(), args.begin(), args.end());
  return run_process("/usr/bin/env", all);
}

fs::path foundation() { return source_dir() / "graphs" / "foundation.json"; }

// A small graph with every kind of writer the foundation has: EXR, 16-bit PNG, RAW16, OBJ, PLY.
fs::path writers_graph(const fs::path& dir) {
  auto doc = nlohmann::json::parse(read_text(foundation()));
  doc["domain"]["resolution"] = {33, 33};
  const fs::path p = dir / "writers.json";
  write_text(p, doc.dump(2));
  return p;
}

std::map<fs::path, std::string> files_under(const fs::path& dir) {
  std::map<fs::path, std::string> files;
  if (!fs::exists(dir)) return files;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) files[fs::relative(e.path(), dir)] = read_text(e.path());
  return files;
}

// EXR headers carry the time of writing (capDate); everything else must match byte for byte.
std::string without_date(const fs::path& name, std::string bytes) {
  if (name.extension() != ".exr") return bytes;
  const std::string tag("capDate\0string\0", 15);
  if (const auto at = bytes.find(tag); at != std::string::npos && at + tag.size() + 4 + 19 <= bytes.size())
    std::fill_n(bytes.begin() + static_cast<std::ptrdiff_t>(at + tag.size() + 4), 19, '0');
  return bytes;
}

// Same file names and contents (up to EXR dates); reports names only.
::testing::AssertionResult same_files(const std::map<fs::path, std::string>& a,
                                      const std::map<fs::path, std::string>& b) {
  std::string diff;
  for (const auto& [name, bytes] : a) {
    if (!b.count(name))
      diff += " missing:" + name.string();
    else if (without_date(name, bytes) != without_date(name, b.at(name)))
      diff += " differs:" + name.string();
  }
  for (const auto& [name, bytes] : b)
    if (!a.count(name)) diff += " extra:" + name.string();
  if (diff.empty()) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << diff;
}

std::vector<fs::path> temporaries_under(const fs::path& dir) {
  std::vector<fs::path> found;
  if (!fs::exists(dir)) return found;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (is_temporary_name(e.path().filename().string())) found.push_back(e.path());
  return found;
}

std::string constant_graph(const std::string& path,
                           const std::string& domain = R"({ "size": [100, 100], "resolution": [16, 16] })") {
  return R"({ "format": "orogen-graph", "version": 1, "domain": )" + domain + R"(,
  "nodes": [
    { "id": "flat", "type": "Constant", "params": { "value": 5 } },
    { "id": "save", "type": "WriteHeightfield", "inputs": { "height": "flat.out" }, "params": { "path": )" +
         nlohmann::json(path).dump() + R"( } }
  ]
})";
}

// Every entry of a cache directory loads as valid.
void expect_cache_valid(const fs::path& cache) {
  ASSERT_TRUE(fs::exists(cache));
  const DiskCache disk(cache);
  std::size_t entries = 0;
  for (const auto& e : fs::recursive_directory_iterator(cache)) {
    if (!e.is_regular_file() || e.path().extension() != ".orc") continue;
    ++entries;
    const auto loaded = disk.load(CacheKey::from_hex(e.path().stem().string()));
    EXPECT_FALSE(loaded.rejected) << loaded.reason;
    EXPECT_TRUE(loaded.result) << e.path();
  }
  EXPECT_GT(entries, 0u);
}

// ---------------------------------------------------------------------------------------------------------
// 1. A full disk never destroys the previous output, and the run fails.

TEST(FullDisk, InjectedWriteFailureKeepsEveryPreviousFileAndExitsOne) {
  const auto dir = scratch_dir("full-disk-injected");
  const auto graph = writers_graph(dir);
  const auto out = dir / "out";
  ASSERT_EQ(orogen({"eval", graph.string(), "-o", out.string(), "-q"}).exit_code, 0);
  const auto before = files_under(out);
  ASSERT_GE(before.size(), 5u);
  // Budgets: nothing at all, and part-way through the first file (a few KB then ENOSPC).
  for (const char* budget : {"0", "3000", "20000"}) {
    SCOPED_TRACE(std::string("bytes allowed: ") + budget);
    auto doc = nlohmann::json::parse(read_text(graph));
    doc["nodes"][2]["params"]["value"] = 21;  // a different result, so every writer runs again
    write_text(dir / "changed.json", doc.dump());
    const auto r = orogen_env({std::string("OROGEN_TEST_ENOSPC_AFTER_BYTES=") + budget},
                              {"eval", (dir / "changed.json").string(), "-o", out.string(), "-q"});
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_NE(r.err.find("disk or quota is full"), std::string::npos) << r.err;
    // Every file is either the old one, byte for byte, or (written before the budget ran out) complete.
    const auto after = files_under(out);
    std::size_t kept = 0;
    for (const auto& [name, bytes] : before) {
      ASSERT_TRUE(after.count(name)) << name << " disappeared";
      kept += without_date(name, after.at(name)) == without_date(name, bytes);
    }
    if (std::string(budget) == "0") {
      EXPECT_EQ(kept, before.size()) << "with no byte writable, nothing may change";
    }
    EXPECT_TRUE(temporaries_under(out).empty());
  }
}

TEST(FullDisk, CheckedFileReportsShortWriteAndFinishThrows) {
  const auto dir = scratch_dir("full-disk-unit");
  inject_write_failure_after(10);
  CheckedFile f(dir / "x");
  EXPECT_FALSE(f.write("0123456789abcdef", 16));
  EXPECT_FALSE(f.ok());
  EXPECT_THROW(f.finish(), WriteError);
  inject_write_failure_after(-1);
}

// A real full file system: a 512 KiB tmpfs mounted in a private mount namespace (unshare -rm), when the
// kernel allows it; skipped otherwise.
TEST(FullDisk, RealSmallTmpfsKeepsThePreviousFile) {
  if (::access("/usr/bin/unshare", X_OK) != 0) GTEST_SKIP() << "no unshare";
  const auto dir = scratch_dir("full-disk-tmpfs");
  const auto mnt = dir / "mnt";
  fs::create_directories(mnt);
  const auto probe =
      run_process("/usr/bin/unshare", {"-rm", "sh", "-c", "mount -t tmpfs -o size=64k tmpfs " + mnt.string()});
  if (probe.exit_code != 0) GTEST_SKIP() << "cannot mount a tmpfs here: " << probe.err;
  // Small first (fits), then 257x257 (about 260 KB EXR, 130 KB PNG) on a disk with only the rest free.
  write_text(dir / "small.json", constant_graph("h.exr"));
  write_text(dir / "big.json", R"({ "format": "orogen-graph", "version": 6,
    "domain": { "size": [100, 100], "resolution": [257, 257] },
    "nodes": [ { "id": "n", "type": "Perlin", "params": { "feature_size": 3 } },
               { "id": "save", "type": "WriteHeightfield", "inputs": { "in": "n.out" },
                 "params": { "path": "h.exr" } } ] })");
  const std::string cli = cli_binary().string(), m = mnt.string();
  const std::string script = "set -u; mount -t tmpfs -o size=256k tmpfs " + m + " || exit 90; " + cli + " eval " +
                             (dir / "small.json").string() + " -o " + m + "/out -q || exit 91; cp " + m +
                             "/out/h.exr " + (dir / "before.exr").string() + "; " + "dd if=/dev/zero of=" + m +
                             "/fill bs=1k count=200 2>/dev/null; " + cli + " eval " + (dir / "big.json").string() +
                             " -o " + m + "/out -q; rc=$?; cmp -s " + m + "/out/h.exr " +
                             (dir / "before.exr").string() + " && echo SAME; ls -a " + m + "/out; exit $rc";
  const auto r = run_process("/usr/bin/unshare", {"-rm", "sh", "-c", script});
  ASSERT_NE(r.exit_code, 90) << r.err;
  ASSERT_NE(r.exit_code, 91) << r.err;
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_NE(r.out.find("SAME"), std::string::npos) << "the previous file changed: " << r.out;
  EXPECT_EQ(r.out.find(".orogen-tmp-"), std::string::npos) << "a temporary was left: " << r.out;
  EXPECT_NE(r.err.find("No space left on device"), std::string::npos) << r.err;
}

// Issue #30, defect 8 end to end: WriteScene with `instancing: nodes` on about 280,000 instances needs about
// 600 MB (tinygltf's JSON document of one node per instance); under an address-space limit that cannot hold
// it, `orogen eval` fails the node (exit 1, the node named on stderr) instead of aborting inside tinygltf's
// writer. The limit (prlimit --as) counts every mapping, so it is set above what the binary needs to start
// (probed first with a tiny graph: skipped where that does not fit) and far below what the scene needs.
// Skipped under AddressSanitizer, whose shadow memory needs terabytes of address space.
TEST(OutOfMemory, WriteSceneOfInstanceNodesUnderAnAddressSpaceLimitFailsTheNode) {
#ifdef OROGEN_TEST_ASAN
  GTEST_SKIP() << "AddressSanitizer reserves more address space than any limit allows";
#endif
  if (::access("/usr/bin/prlimit", X_OK) != 0 || ::access("/usr/bin/timeout", X_OK) != 0)
    GTEST_SKIP() << "no prlimit or timeout";
  const auto dir = scratch_dir("address-space-limit");
  // Without OpenImageIO mapped at start-up (it is loaded only for image files, issue 27) the process is ~200 MB
  // of address space smaller: at 448 MB the scene's serialization fails cleanly, and the probe writes a RAW file so
  // it, too, runs without the image codec. (The writer reserves the address space of tinygltf's JSON tree before
  // building it, nodes/io/gltf_bytes.cpp: a std::bad_alloc inside that tree aborted the process in about one run of
  // four.)
  const std::string limit = "--as=" + std::to_string(448ull << 20);
  // Two worker threads and two malloc arenas: the address space the process needs does not grow with the cores.
  const auto limited = [&](const fs::path& graph) {
    return run_process("/usr/bin/env", {"MALLOC_ARENA_MAX=2", "/usr/bin/timeout", "60", "/usr/bin/prlimit", limit,
                                        cli_binary().string(), "eval", graph.string(), "-q", "--threads", "2", "-o",
                                        (dir / "out").string()});
  };
  write_text(dir / "probe.json", constant_graph("probe.r16"));
  const auto probe = limited(dir / "probe.json");
  if (probe.exit_code != 0) GTEST_SKIP() << "orogen does not run within " << limit << " here: " << probe.err;
  write_text(dir / "scene.json", R"({ "format": "orogen-graph", "version": 6,
    "domain": { "origin": [0, 0], "size": [300, 300], "resolution": [33, 33] },
    "nodes": [
      { "id": "spots", "type": "PoissonDisk", "params": { "radius_0": 0.5 } },
      { "id": "rock", "type": "HullRock" },
      { "id": "scene", "type": "Instance", "inputs": { "in": "spots.out", "mesh_0": "rock.out" } },
      { "id": "save", "type": "WriteScene", "inputs": { "in": "scene.out" },
        "params": { "path": "scene.gltf", "instancing": "nodes" } } ] })");
  const auto r = limited(dir / "scene.json");
  EXPECT_EQ(r.exit_code, 1) << "exit " << r.exit_code << " (124: a hang, 134: an abort): " << r.err;
  EXPECT_NE(r.err.find("node 'save'"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("memory"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("terminate called"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "out" / "scene.gltf"));
  for (const auto& e : fs::directory_iterator(dir / "out"))
    EXPECT_EQ(e.path().filename().string().find(".orogen-tmp-"), std::string::npos) << "a temporary was left";
}

// ---------------------------------------------------------------------------------------------------------
// 2. A symbolic link inside the output folder or the cache does not let a graph write outside them.

TEST(SymlinkEscape, LinkInOutputFolderIsRefused) {
  const auto dir = scratch_dir("symlink-escape");
  const auto out = dir / "out", elsewhere = dir / "elsewhere";
  fs::create_directories(out);
  fs::create_directories(elsewhere);
  fs::create_directory_symlink(elsewhere, out / "link");
  write_text(dir / "g.json", constant_graph("link/escaped.exr"));
  const auto r = orogen({"eval", (dir / "g.json").string(), "-o", out.string(), "-q"});
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("leaves the output directory"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::is_empty(elsewhere)) << "a file was written outside the output folder";
  // A deeper path through the link creates no directory there either.
  write_text(dir / "g2.json", constant_graph("link/sub/deeper/escaped.exr"));
  EXPECT_EQ(orogen({"eval", (dir / "g2.json").string(), "-o", out.string(), "-q"}).exit_code, 1);
  EXPECT_TRUE(fs::is_empty(elsewhere));
  // A link that stays inside the output folder is fine, and --allow-any-path allows the escape.
  fs::create_directories(out / "real");
  fs::create_directory_symlink(out / "real", out / "inside");
  write_text(dir / "g3.json", constant_graph("inside/ok.exr"));
  EXPECT_EQ(orogen({"eval", (dir / "g3.json").string(), "-o", out.string(), "-q"}).exit_code, 0);
  EXPECT_TRUE(fs::exists(out / "real" / "ok.exr"));
  EXPECT_EQ(orogen({"eval", (dir / "g.json").string(), "-o", out.string(), "-q", "--allow-any-path"}).exit_code, 0);
  EXPECT_TRUE(fs::exists(elsewhere / "escaped.exr"));
}

TEST(SymlinkEscape, OutputDirectorySpellingsAreAccepted) {
  const auto dir = scratch_dir("output-spellings");
  for (const std::string spelling : {"out", "out/", "./out", "./out/", "out/./"}) {
    SCOPED_TRACE(spelling);
    const auto prev = fs::current_path();
    fs::current_path(dir);
    OutputPolicy policy{spelling, false};
    EXPECT_NO_THROW(prepare_output_directory(policy, resolve_output_path(policy, "a/b/c.exr")));
    EXPECT_NO_THROW(prepare_output_directory(policy, resolve_output_path(policy, "top.exr")));
    fs::current_path(prev);
  }
  EXPECT_TRUE(fs::is_directory(dir / "out" / "a" / "b"));
}

TEST(SymlinkEscape, CacheSubdirectoryLinksAreNotFollowed) {
  const auto dir = scratch_dir("symlink-cache");
  const auto cache = dir / "cache", elsewhere = dir / "elsewhere";
  fs::create_directories(cache);
  fs::create_directories(elsewhere);
  // Every possible subdirectory is a link out of the cache.
  for (int k = 0; k < 256; ++k) {
    char name[3];
    std::snprintf(name, sizeof name, "%02x", k);
    fs::create_directory_symlink(elsewhere, cache / name);
  }
  write_text(dir / "g.json", constant_graph("h.exr"));
  const auto r =
      orogen({"eval", (dir / "g.json").string(), "-o", (dir / "out").string(), "--cache-dir", cache.string(), "-q"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::is_empty(elsewhere)) << "a cache entry was written through a link";
  expect_cache_valid(cache);
}

// ---------------------------------------------------------------------------------------------------------
// 3. Control characters in a path are refused when the graph is loaded; a failed write removes only its
// own temporary.

TEST(ControlCharacters, NulAndControlCharactersInPathsRefusedAtLoad) {
  const auto dir = scratch_dir("control-chars");
  for (const char* path : {"a\\u0000b.exr", "\\u0000", "a\\nb.exr", "x\\u001b[2J.exr", "a\\u007fb.exr"}) {
    SCOPED_TRACE(path);
    const std::string text = R"({ "format": "orogen-graph", "version": 1,
      "domain": { "size": [100, 100], "resolution": [16, 16] },
      "nodes": [ { "id": "flat", "type": "Constant" },
                 { "id": "save", "type": "WriteHeightfield", "inputs": { "height": "flat.out" },
                   "params": { "path": ")" +
                             std::string(path) + R"(" } } ] })";
    write_text(dir / "g.json", text);
    const auto v = orogen({"validate", (dir / "g.json").string()});
    EXPECT_EQ(v.exit_code, 2) << v.out;
    EXPECT_NE(v.err.find("control character"), std::string::npos) << v.err;
    fs::create_directories(dir / "out");
    const auto e = orogen({"eval", (dir / "g.json").string(), "-o", (dir / "out").string(), "-q"});
    EXPECT_EQ(e.exit_code, 2);
    EXPECT_TRUE(fs::is_directory(dir / "out")) << "the output folder was deleted";
  }
}

TEST(ControlCharacters, FailedWriteRemovesOnlyItsTemporary) {
  const auto dir = scratch_dir("cleanup-own-temp") / "out";
  fs::create_directories(dir);
  // The writer fails before creating anything: the (empty) folder stays.
  EXPECT_THROW(write_file_atomically(dir / "a.exr", [](const fs::path&) { throw std::runtime_error("no"); }),
               std::runtime_error);
  EXPECT_TRUE(fs::is_directory(dir));
  // A NUL in the name is refused before anything is created or removed.
  EXPECT_THROW(write_file_atomically(dir / std::string("a\0b", 3), [](const fs::path& t) { write_text(t, "x"); }),
               std::runtime_error);
  EXPECT_TRUE(fs::is_directory(dir));
  EXPECT_TRUE(fs::is_empty(dir));
}

// ---------------------------------------------------------------------------------------------------------
// 4. Any legal file name can be written: the temporary name is short.

TEST(LongFileName, NamesUpTo255BytesAreWritten) {
  const auto dir = scratch_dir("long-name");
  for (std::size_t length : {244u, 255u}) {
    const std::string name = std::string(length - 4, 'n') + ".exr";
    write_text(dir / "g.json", constant_graph(name));
    const auto r = orogen({"eval", (dir / "g.json").string(), "-o", (dir / "out").string(), "-q"});
    EXPECT_EQ(r.exit_code, 0) << length << ": " << r.err;
    EXPECT_TRUE(fs::exists(dir / "out" / name)) << length;
  }
}

// ---------------------------------------------------------------------------------------------------------
// 5. A damaged cache entry of any kind is recomputed; the cache never fails a build.

TEST(DamagedCache, EveryKindOfDamageIsRecomputed) {
  const auto dir = scratch_dir("damaged-cache");
  const auto graph = writers_graph(dir);
  const auto cache = dir / "cache";
  auto eval = [&](const fs::path& out) {
    return orogen({"eval", graph.string(), "-o", out.string(), "--cache-dir", cache.string(), "-q"});
  };
  ASSERT_EQ(eval(dir / "ref").exit_code, 0);
  const auto reference = files_under(dir / "ref");
  using Damage = std::function<void(const fs::path&)>;
  const std::vector<std::pair<std::string, Damage>> damages = {
      {"directory",
       [](const fs::path& p) {
         fs::remove(p);
         fs::create_directories(p / "inner");
       }},
      {"empty", [](const fs::path& p) { write_text(p, ""); }},
      {"truncated", [](const fs::path& p) { fs::resize_file(p, fs::file_size(p) / 2); }},
      {"too long", [](const fs::path& p) { std::ofstream(p, std::ios::app) << "trailing"; }},
      {"checksum",
       [](const fs::path& p) {
         std::fstream f(p, std::ios::in | std::ios::out | std::ios::binary);
         f.seekp(static_cast<std::streamoff>(DiskCache::kHeaderBytes + 3));
         f.put('\x5a');
       }},
      {"version",
       [](const fs::path& p) {
         std::fstream f(p, std::ios::in | std::ios::out | std::ios::binary);
         f.seekp(8);
         f.put('\x7f');
       }},
      {"fifo",
       [](const fs::path& p) {
         fs::remove(p);
         ::mkfifo(p.c_str(), 0644);
       }},
      {"dangling link",
       [](const fs::path& p) {
         fs::remove(p);
         fs::create_symlink("/nonexistent/x", p);
       }},
      {"link to a file",
       [&](const fs::path& p) {
         fs::remove(p);
         fs::create_symlink(graph, p);
       }},
      {"subdirectory is a file",
       [](const fs::path& p) {
         fs::remove_all(p.parent_path());
         write_text(p.parent_path(), "x");
       }},
  };
  for (const auto& [what, damage] : damages) {
    SCOPED_TRACE(what);
    std::vector<fs::path> entries;
    for (const auto& e : fs::recursive_directory_iterator(cache))
      if (e.path().extension() == ".orc" && fs::is_regular_file(fs::symlink_status(e.path())))
        entries.push_back(e.path());
    ASSERT_FALSE(entries.empty());
    for (const auto& entry : entries) damage(entry);
    const auto out = scratch_dir("damaged-cache-out");
    const auto r = eval(out);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(same_files(files_under(out), reference)) << "the recomputed outputs differ";
    // Clean again for the next kind of damage.
    ASSERT_EQ(eval(scratch_dir("damaged-cache-out")).exit_code, 0);
  }
  // (Entries of nodes the runs never needed again may still be damaged: they are rejected when looked up.)
}

// ---------------------------------------------------------------------------------------------------------
// 6. Numeric options: finite, in range, or a usage error (exit 2).

TEST(NumericOptions, NonFiniteAndOutOfRangeAreUsageErrors) {
  const auto dir = scratch_dir("numeric-options");
  write_text(dir / "g.json", constant_graph("h.exr"));
  const std::vector<std::vector<std::string>> bad = {
      {"--cache-mb", "nan"},   {"--cache-mb", "inf"},   {"--cache-mb", "1e20"},     {"--cache-mb", "-1"},
      {"--cache-mb", "12abc"}, {"--cache-mb", "-nan"},  {"--cache-disk-mb", "nan"}, {"--cache-disk-mb", "1e300"},
      {"--max-memory", "inf"}, {"--max-memory", "-5G"}, {"--max-memory", "0"},      {"--max-memory", "12Q"},
      {"--threads", "1e20"},   {"--threads", "-1"},     {"--resolution", "nanxnan"}};
  for (const auto& option : bad) {
    std::vector<std::string> args = {"eval", (dir / "g.json").string(), "-o", (dir / "out").string(), "-q"};
    args.insert(args.end(), option.begin(), option.end());
    const auto r = orogen(args);
    EXPECT_EQ(r.exit_code, 2) << option[0] << " " << option[1] << ": " << r.err;
  }
  EXPECT_EQ(orogen({"eval", (dir / "g.json").string(), "-o", (dir / "out").string(), "-q", "--cache-mb", "0.5",
                    "--cache-disk-mb", "10", "--max-memory", "1G"})
                .exit_code,
            0);
}

// ---------------------------------------------------------------------------------------------------------
// 7. Non-finite values: every lookup is total; NaN in gives NaN out (the documented rule).

TEST(NonFinite, CurveEvaluateOfNaNIsNaNAndInfinitiesClamp) {
  CurveValue c;
  c.points = {{0.0, 0.0}, {0.5, 0.8}, {1.0, 1.0}};
  EXPECT_TRUE(std::isnan(c.evaluate(std::numeric_limits<double>::quiet_NaN())));
  EXPECT_EQ(c.evaluate(std::numeric_limits<double>::infinity()), 1.0);
  EXPECT_EQ(c.evaluate(-std::numeric_limits<double>::infinity()), 0.0);
  GradientValue g;
  g.stops = {{0.0, glm::vec4(0, 0, 0, 1)}, {1.0, glm::vec4(1, 1, 1, 1)}};
  EXPECT_TRUE(std::isnan(g.evaluate(std::numeric_limits<double>::quiet_NaN()).r));
}

TEST(NonFinite, BicubicAndBilinearLookupsOfNaNAreNaN) {
  const Domain d = Domain::from_extent({0, 0}, {10, 10}, {8, 8});
  Heightfield f(d);
  for (int j = 0; j < 8; ++j)
    for (int i = 0; i < 8; ++i) f.at(i, j) = static_cast<float>(i + j);
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(std::isnan(catmull_rom(f, nan, 2.0)));
  EXPECT_TRUE(std::isnan(catmull_rom(f, 2.0, nan)));
  EXPECT_EQ(catmull_rom(f, inf, 0.0), f.at(7, 0));
  EXPECT_EQ(catmull_rom(f, -1e300, 0.0), f.at(0, 0));
  EXPECT_TRUE(std::isnan(f.bilinear(nan, 1.0)));
  EXPECT_EQ(f.bilinear(inf, -inf), f.at(7, 0));
}

TEST(NonFinite, NaNDisplacementIntoWarpAndNaNIntoCurveGiveNaNSamples) {
  // End to end through the CLI: inf - inf = NaN made by ordinary nodes, fed to Warp and Curve, then written.
  const auto dir = scratch_dir("nan-warp");
  write_text(dir / "g.json", R"({ "format": "orogen-graph", "version": 6,
    "domain": { "size": [100, 100], "resolution": [16, 16] },
    "nodes": [
      { "id": "big", "type": "Constant", "params": { "value": 1e6 } },
      { "id": "e12", "type": "Multiply", "inputs": { "a": "big.out", "b": "big.out" } },
      { "id": "e24", "type": "Multiply", "inputs": { "a": "e12.out", "b": "e12.out" } },
      { "id": "inf", "type": "Multiply", "inputs": { "a": "e24.out", "b": "e24.out" } },
      { "id": "nan", "type": "Subtract", "inputs": { "a": "inf.out", "b": "inf.out" } },
      { "id": "ramp", "type": "LinearGradient" },
      { "id": "warp", "type": "Warp", "inputs": { "in": "ramp.out", "dx": "nan.out", "dy": "nan.out" } },
      { "id": "curve", "type": "Curve", "inputs": { "in": "nan.out" } },
      { "id": "w1", "type": "WriteHeightfield", "inputs": { "in": "warp.out" }, "params": { "path": "warp.exr" } },
      { "id": "w2", "type": "WriteHeightfield", "inputs": { "in": "curve.out" }, "params": { "path": "curve.exr" } }
    ] })");
  const auto r = orogen({"eval", (dir / "g.json").string(), "-o", (dir / "out").string(), "-q"});
  // The rule: NaN propagates through nodes; EXR stores it (PNG/RAW writers refuse non-finite heights).
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

// ---------------------------------------------------------------------------------------------------------
// 8. Degenerate domains are refused; kernels are bounded.

TEST(DegenerateDomain, TinyHugeAndNonFiniteDomainsAreRefused) {
  const auto dir = scratch_dir("degenerate-domain");
  for (const std::string domain : {R"({ "size": [5e-324, 5e-324], "resolution": [16, 16] })",
                                   R"({ "size": [1e-9, 1e-9], "resolution": [16, 16] })",
                                   R"({ "size": [100, 100], "resolution": [16, 16], "origin": [1e300, 0] })",
                                   R"({ "size": [1e308, 1e308], "resolution": [16, 16] })"}) {
    SCOPED_TRACE(domain);
    write_text(dir / "g.json", constant_graph("h.exr", domain));
    const auto v = orogen({"validate", (dir / "g.json").string()});
    EXPECT_EQ(v.exit_code, 2) << v.out;
    EXPECT_NE(v.err.find("domain"), std::string::npos) << v.err;
  }
  Domain d = Domain::from_extent({0, 0}, {5e-324, 5e-324}, {16, 16});
  EXPECT_FALSE(check_domain(d).empty());
  EXPECT_TRUE(check_domain(Domain::from_extent({0, 0}, {100, 50}, {16, 9})).empty());
}

TEST(DegenerateDomain, MeshWithColorsOnSmallestDomainAndBlurOnTinyDomainFinish) {
  const auto dir = scratch_dir("tiny-domain-blur");
  // The smallest accepted spacing (1e-6 m) with a 1 km blur: the kernel is bounded by the field.
  write_text(dir / "g.json", R"({ "format": "orogen-graph", "version": 6,
    "domain": { "size": [1.5e-5, 1.5e-5], "resolution": [16, 16] },
    "nodes": [
      { "id": "n", "type": "LinearGradient", "params": { "from": 0, "to": 1e-5 } },
      { "id": "b", "type": "Blur", "inputs": { "in": "n.out" }, "params": { "sigma": 1000 } },
      { "id": "c", "type": "ColorRamp", "inputs": { "in": "n.out" } },
      { "id": "m", "type": "HeightfieldToMesh", "inputs": { "in": "n.out", "colors": "c.out" } },
      { "id": "wm", "type": "WriteMesh", "inputs": { "in": "m.out" }, "params": { "path": "m.ply" } },
      { "id": "w", "type": "WriteHeightfield", "inputs": { "in": "b.out" }, "params": { "path": "b.exr" } }
    ] })");
  const auto r = orogen({"eval", (dir / "g.json").string(), "-o", (dir / "out").string(), "-q"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

// ---------------------------------------------------------------------------------------------------------
// 9. Huge requests are refused before allocating, naming the node and the bytes; graph files are capped.

TEST(HugeRequest, ResolutionBeyondMemoryIsRefusedUpFront) {
  const auto dir = scratch_dir("huge-request");
  write_text(dir / "g.json", constant_graph("h.exr"));
  const auto r = orogen({"eval", (dir / "g.json").string(), "-o", (dir / "out").string(), "-q", "--resolution",
                         "65536x65536", "--max-memory", "8G"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("node 'flat'"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("bytes"), std::string::npos) << r.err;
  const auto small =
      orogen({"eval", (dir / "g.json").string(), "-o", (dir / "out").string(), "-q", "--max-memory", "1K"});
  EXPECT_EQ(small.exit_code, 2) << small.err;
}

TEST(HugeRequest, ValidateOfDevZeroAndOfHugeFileExitsTwo) {
  const auto r = orogen({"validate", "/dev/zero"});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("limit"), std::string::npos) << r.err;
}

// ---------------------------------------------------------------------------------------------------------
// 10. Temporaries a killed run left are removed by the next run; live processes' ones are kept.

pid_t dead_pid() {
  const pid_t pid = ::fork();
  if (pid == 0) ::_exit(0);
  int status = 0;
  ::waitpid(pid, &status, 0);
  return pid;
}

TEST(StaleTemporaries, NextRunRemovesOnlyDeadProcessesTemporaries) {
  const auto dir = scratch_dir("stale-temps");
  const auto out = dir / "out", cache = dir / "cache";
  const std::string dead = ".orogen-tmp-" + std::to_string(dead_pid()) + "-0";
  // A temporary in use is one whose lock a live process (here: this one) holds.
  fs::create_directories(out);
  const TemporaryLock lock(out);
  const std::string live = ".orogen-tmp-" + lock.tag() + ".exr";
  write_text(out / (dead + ".exr"), "stale");
  write_text(out / "deep" / "er" / (dead + ".png"), "stale");
  write_text(out / live, "in use");
  write_text(out / ".tmp-1-0.exr", "not ours");
  write_text(cache / "ab" / (dead + ".orc"), "stale");
  write_text(dir / "g.json", constant_graph("h.exr"));
  const auto r = orogen({"eval", (dir / "g.json").string(), "-o", out.string(), "--cache-dir", cache.string(), "-q"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_FALSE(fs::exists(out / (dead + ".exr")));
  EXPECT_FALSE(fs::exists(out / "deep" / "er" / (dead + ".png")));
  EXPECT_FALSE(fs::exists(cache / "ab" / (dead + ".orc")));
  EXPECT_TRUE(fs::exists(out / live)) << "a running process's temporary was removed";
  EXPECT_TRUE(fs::exists(out / ".tmp-1-0.exr")) << "a file not of our naming was removed";
}

// ---------------------------------------------------------------------------------------------------------
// Issue 14: the persistent cache is compressed, bounded (LRU), and safe to share between processes.

TEST(CacheBound, EntriesAreCompressedAndTheDirectoryStaysWithinItsBound) {
  const auto dir = scratch_dir("cache-bound");
  const auto cache = dir / "cache";
  write_text(dir / "g.json", constant_graph("h.exr", R"({ "size": [100, 100], "resolution": [512, 512] })"));
  ASSERT_EQ(
      orogen({"eval", (dir / "g.json").string(), "-o", (dir / "out").string(), "--cache-dir", cache.string(), "-q"})
          .exit_code,
      0);
  std::uint64_t bytes = 0;
  for (const auto& e : fs::recursive_directory_iterator(cache))
    if (e.is_regular_file()) bytes += e.file_size();
  EXPECT_LT(bytes, 512u * 512u * 4u / 20u) << "a constant 512x512 field should compress well";

  // A bound of 0.3 MiB over several distinct noise results (about 0.1 MB each compressed).
  const std::uint64_t bound = 300 * 1024;
  for (int seed = 0; seed < 8; ++seed) {
    write_text(dir / "n.json", R"({ "format": "orogen-graph", "version": 1,
      "domain": { "size": [100, 100], "resolution": [160, 160] },
      "nodes": [ { "id": "n", "type": "Perlin", "params": { "seed": )" +
                                   std::to_string(seed) + R"(, "feature_size": 3 } } ] })");
    ASSERT_EQ(orogen({"eval", (dir / "n.json").string(), "-o", (dir / "out").string(), "--cache-dir", cache.string(),
                      "--cache-disk-mb", "0.29296875", "-q"})
                  .exit_code,
              0);
    const DiskCache disk(cache);
    EXPECT_LE(disk.scan_bytes(), bound) << "after seed " << seed;
  }
}

TEST(CacheBound, LeastRecentlyUsedEntryIsEvictedFirst) {
  const auto dir = scratch_dir("cache-lru");
  DiskCache disk(dir, 1 << 20);
  auto result = [](float v) {
    auto r = CachedResult();
    auto h = std::make_shared<Heightfield>(Domain::from_extent({0, 0}, {1, 1}, {64, 64}));
    std::mt19937 rng(static_cast<unsigned>(v));
    for (auto& x : h->data) x = static_cast<float>(rng()) * v;  // incompressible
    r.outputs.push_back(HeightfieldPtr(h));
    return r;
  };
  std::vector<CacheKey> keys;
  for (int k = 0; k < 4; ++k) {
    keys.push_back(CacheKey{1, static_cast<std::uint64_t>(k)});
    disk.store(keys.back(), result(static_cast<float>(k + 1)));
    std::this_thread::sleep_for(std::chrono::milliseconds(20));  // distinct modification times
  }
  ASSERT_TRUE(disk.load(keys[0]).result);  // the oldest becomes the most recently used
  const std::uint64_t entry = disk.scan_bytes() / 4;
  EXPECT_EQ(disk.evict_to(entry * 2 + entry / 2), 2u);
  EXPECT_TRUE(disk.load(keys[0]).result) << "the recently used entry was evicted";
  EXPECT_FALSE(disk.load(keys[1]).result);
  EXPECT_FALSE(disk.load(keys[2]).result);
  EXPECT_TRUE(disk.load(keys[3]).result);
}

// Two evaluations of the same graph on one cache directory at once, 20 times: both succeed with the same
// outputs as a run alone, and every entry in the directory is valid afterwards. Under AddressSanitizer, where
// a process start costs seconds, 8 rounds (still two with each of the four caches, and a new result after).
TEST(SharedCache, TwoConcurrentEvaluationsTwentyTimes) {
  const auto dir = scratch_dir("shared-cache");
  const auto graph = writers_graph(dir);
  ASSERT_EQ(orogen({"eval", graph.string(), "-o", (dir / "ref").string(), "-q"}).exit_code, 0);
  const auto reference = files_under(dir / "ref");
#if defined(OROGEN_TEST_ASAN)
  const int rounds = 8;
#else
  const int rounds = 20;
#endif
  for (int round = 0; round < rounds; ++round) {
    SCOPED_TRACE("round " + std::to_string(round));
    const auto cache = dir / ("cache" + std::to_string(round % 4));  // reused: hits and misses mix
    auto doc = nlohmann::json::parse(read_text(graph));
    doc["nodes"][2]["params"]["value"] = 20 + round / 4;  // a new result every fourth round
    write_text(dir / "round.json", doc.dump());
    ProcessResult a, b;
    const auto out_a = scratch_dir("shared-a"), out_b = scratch_dir("shared-b");
    std::thread ta([&] {
      a = orogen({"eval", (dir / "round.json").string(), "-o", out_a.string(), "--cache-dir", cache.string(), "-q"});
    });
    std::thread tb([&] {
      b = orogen({"eval", (dir / "round.json").string(), "-o", out_b.string(), "--cache-dir", cache.string(), "-q"});
    });
    ta.join();
    tb.join();
    EXPECT_EQ(a.exit_code, 0) << a.err;
    EXPECT_EQ(b.exit_code, 0) << b.err;
    EXPECT_TRUE(same_files(files_under(out_a), files_under(out_b)));
    if (round < 4) {
      EXPECT_TRUE(same_files(files_under(out_a), reference));
    }
    expect_cache_valid(cache);
    EXPECT_TRUE(temporaries_under(cache).empty());
  }
}

// ---------------------------------------------------------------------------------------------------------
// kill -9 at random moments of an evaluation with writers and a cache: previous outputs intact, cache entries
// absent or valid, no temporaries after the next run, and that run byte-identical to a clean one.

TEST(KillNine, RandomMomentsLeaveOutputsAndCacheConsistent) {
  const auto dir = scratch_dir("kill-nine");
  const auto graph = writers_graph(dir);
  auto doc = nlohmann::json::parse(read_text(graph));
  doc["domain"]["resolution"] = {129, 129};
  write_text(graph, doc.dump());
  // The outputs of each value the rounds use: a file after a kill must be one of these, whole.
  std::vector<std::map<fs::path, std::string>> results;
  for (int v = 20; v < 23; ++v) {
    auto d = doc;
    d["nodes"][2]["params"]["value"] = v;
    write_text(dir / "v.json", d.dump());
    const auto o = dir / ("clean" + std::to_string(v));
    ASSERT_EQ(orogen({"eval", (dir / "v.json").string(), "-o", o.string(), "-q"}).exit_code, 0);
    results.push_back(files_under(o));
  }
  const auto& clean = results[0];
  const auto out = dir / "out", cache = dir / "cache";
  ASSERT_EQ(orogen({"eval", graph.string(), "-o", out.string(), "-q"}).exit_code, 0);  // the previous outputs
  std::mt19937 rng(12345);
  for (int round = 0; round < 12; ++round) {
    SCOPED_TRACE("round " + std::to_string(round));
    // A changed parameter and back, so writers and the cache are busy when the kill comes.
    auto changed = doc;
    changed["nodes"][2]["params"]["value"] = 20 + (round % 3);
    write_text(dir / "k.json", changed.dump());
    const pid_t pid = ::fork();
    if (pid == 0) {
      const int null = ::open("/dev/null", O_WRONLY);
      ::dup2(null, 1);
      ::dup2(null, 2);
      const std::string cli = cli_binary().string(), g = (dir / "k.json").string(), o = out.string(),
                        c = cache.string();
      ::execl(cli.c_str(), cli.c_str(), "eval", g.c_str(), "-o", o.c_str(), "--cache-dir", c.c_str(), "-q", nullptr);
      ::_exit(127);
    }
    std::this_thread::sleep_for(std::chrono::microseconds(std::uniform_int_distribution<int>(0, 400000)(rng)));
    ::kill(pid, SIGKILL);
    int status = 0;
    ::waitpid(pid, &status, 0);
    // Every output file is whole: one of the graph's results (the previous ones or a complete new one).
    for (const auto& [name, bytes] : files_under(out)) {
      if (is_temporary_name(name.filename().string())) continue;
      bool whole = false;
      for (const auto& r : results)
        whole = whole || (r.count(name) && without_date(name, r.at(name)) == without_date(name, bytes));
      EXPECT_TRUE(whole) << name << " is not a complete output of the graph";
    }
    // Every cache entry is absent or valid.
    if (fs::exists(cache)) {
      const DiskCache disk(cache);
      for (const auto& e : fs::recursive_directory_iterator(cache))
        if (e.path().extension() == ".orc") {
          const auto loaded = disk.load(CacheKey::from_hex(e.path().stem().string()));
          EXPECT_FALSE(loaded.rejected) << loaded.reason;
        }
    }
  }
  // The next run removes what the killed ones left and is byte-identical to a clean run.
  const auto r = orogen({"eval", graph.string(), "-o", out.string(), "--cache-dir", cache.string(), "-q"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(same_files(files_under(out), clean));
  EXPECT_TRUE(temporaries_under(out).empty());
  EXPECT_TRUE(temporaries_under(cache).empty());
}

}  // namespace
}  // namespace orogen::test
