// The image codec module (nodes/io/image_codec.h) is loaded only when an image file is read or written that
// libpng and OpenEXR do not handle themselves (nodes/io/native): the CLI's start-up, `nodes`, `validate`,
// graphs without image files and graphs that write PNG or EXR files or read PNG and EXR heights never map OpenImageIO
// (issue 27: it cost every start ~0.6 s of CPU and 130 MB), and a module that cannot be loaded gives an error
// naming its path.
#include <gtest/gtest.h>

#include "support/run_process.h"
#include "support/sanitizers.h"
#include "support/test_paths.h"

namespace orogen::test {
namespace {

namespace fs = std::filesystem;

// The CLI with `env` (NAME=VALUE entries) added to its environment, through env(1).
ProcessResult orogen_with(const std::vector<std::string>& env, const std::vector<std::string>& args) {
  std::vector<std::string> all = env;
  all.push_back(cli_binary().string());
  all.insert(all.end(), args.begin(), args.end());
  return run_process("/usr/bin/env", all);
}

// A constant heightfield written to `path` (the extension picks the format: .r16 needs no image codec).
std::string graph_writing(const std::string& path) {
  return R"({
  "format": "orogen-graph", "version": 6,
  "domain": { "size": [100, 100], "resolution": [16, 16] },
  "nodes": [
    { "id": "flat", "type": "Constant", "params": { "value": 5 } },
    { "id": "save", "type": "WriteHeightfield", "inputs": { "in": "flat.out" }, "params": { "path": ")" +
         path + R"(" } }
  ]
})";
}

// What the dynamic loader reports loading (LD_DEBUG=files: every library mapped, at start or by dlopen).
std::string loaded_files(const std::vector<std::string>& args, int expected_exit = 0) {
  const ProcessResult r = orogen_with({"LD_DEBUG=files"}, args);
  EXPECT_EQ(r.exit_code, expected_exit) << r.err.substr(r.err.size() > 4000 ? r.err.size() - 4000 : 0);
  return r.err;
}

TEST(ImageCodec, LoadedOnlyWhenAGraphWritesAnImageTheNativeWritersDoNot) {
#if defined(OROGEN_TEST_ASAN)
  GTEST_SKIP() << "the sanitizer build loads the codec at start (nodes/CMakeLists.txt)";
#endif
  const fs::path dir = scratch_dir("image-codec");
  write_text(dir / "raw.json", graph_writing("flat.r16"));
  write_text(dir / "exr.json", graph_writing("flat.exr"));
  // The control: writing a TIFF loads the module and OpenImageIO, and the loader says so.
  write_text(dir / "tif.json", graph_writing("flat.tif"));
  const std::string tif = loaded_files({"eval", "-q", (dir / "tif.json").string(), "-o", (dir / "out").string()});
  EXPECT_NE(tif.find("orogen_image_codec.so"), std::string::npos) << "LD_DEBUG did not report the module";
  EXPECT_NE(tif.find("libOpenImageIO"), std::string::npos);
  ASSERT_TRUE(fs::exists(dir / "out" / "flat.tif"));
  write_text(dir / "png.json", graph_writing("flat.png"));
  // Heights read back from them: libpng and OpenEXR read those without the codec (nodes/io/native).
  for (const std::string format : {"exr", "png"})
    write_text(dir / ("read_" + format + ".json"), R"({
  "format": "orogen-graph", "version": 7,
  "domain": { "size": [100, 100], "resolution": [16, 16] },
  "nodes": [
    { "id": "read", "type": "ReadHeightfield", "params": { "path": "out/flat.)" +
                                                       format + R"(" } },
    { "id": "save", "type": "WriteHeightfield", "inputs": { "in": "read.out" }, "params": { "path": "back_)" +
                                                       format + R"(.r16" } }
  ]
})");

  const std::vector<std::vector<std::string>> without_images = {
      {"--help"},
      {"nodes"},
      {"nodes", "WriteImage"},
      {"validate", (source_dir() / "graphs" / "terrain.json").string()},
      {"validate", (dir / "exr.json").string()},
      {"eval", "-q", (dir / "raw.json").string(), "-o", (dir / "out").string()},
      {"eval", "-q", (dir / "exr.json").string(), "-o", (dir / "out").string()},
      {"eval", "-q", (dir / "png.json").string(), "-o", (dir / "out").string()},
      {"eval", "-q", (dir / "read_exr.json").string(), "-o", (dir / "out").string()},
      {"eval", "-q", (dir / "read_png.json").string(), "-o", (dir / "out").string()},
  };
  for (const auto& args : without_images) {
    SCOPED_TRACE(args.front() + (args.size() > 1 ? " " + args[1] : std::string()));
    const std::string files = loaded_files(args);
    EXPECT_NE(files.find("file="), std::string::npos) << "LD_DEBUG reported nothing";
    EXPECT_EQ(files.find("OpenImageIO"), std::string::npos) << "OpenImageIO was loaded";
    EXPECT_EQ(files.find("orogen_image_codec"), std::string::npos) << "the image codec module was loaded";
  }
  EXPECT_TRUE(fs::exists(dir / "out" / "flat.r16"));
  EXPECT_TRUE(fs::exists(dir / "out" / "flat.exr"));
  EXPECT_TRUE(fs::exists(dir / "out" / "back_exr.r16"));
  EXPECT_TRUE(fs::exists(dir / "out" / "back_png.r16"));
}

TEST(ImageCodec, MissingModuleNamesThePathAndTheOverride) {
  const fs::path dir = scratch_dir("image-codec-missing");
  write_text(dir / "tif.json", graph_writing("flat.tif"));
  for (const std::string format : {"r16", "exr", "png"})
    write_text(dir / (format + ".json"), graph_writing("flat." + format));
  const std::string missing = "/nonexistent/orogen_image_codec.so";
  const ProcessResult r = orogen_with({"OROGEN_IMAGE_CODEC=" + missing},
                                      {"eval", "-q", (dir / "tif.json").string(), "-o", (dir / "out").string()});
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("save"), std::string::npos) << r.err;  // the failing writer
  EXPECT_NE(r.err.find("cannot load the image codec module"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("'" + missing + "'"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("OROGEN_IMAGE_CODEC"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "out" / "flat.tif"));

  // Formats of Orogen's own, and EXR and PNG (written by OpenEXR and libpng themselves), need no module.
  for (const std::string format : {"r16", "exr", "png"}) {
    const ProcessResult ok =
        orogen_with({"OROGEN_IMAGE_CODEC=" + missing},
                    {"eval", "-q", (dir / (format + ".json")).string(), "-o", (dir / "out").string()});
    EXPECT_EQ(ok.exit_code, 0) << ok.err;
    EXPECT_TRUE(fs::exists(dir / "out" / ("flat." + format)));
  }

  // A file that is not a module: the loader's reason is given.
  write_text(dir / "not_a_module.so", std::string(4096, 'x'));
  const ProcessResult bad = orogen_with({"OROGEN_IMAGE_CODEC=" + (dir / "not_a_module.so").string()},
                                        {"eval", "-q", (dir / "tif.json").string(), "-o", (dir / "out").string()});
  EXPECT_EQ(bad.exit_code, 1) << bad.err;
  // dlerror() names the file, then the reason.
  EXPECT_NE(bad.err.find("(" + (dir / "not_a_module.so").string() + ": "), std::string::npos) << bad.err;
}

}  // namespace
}  // namespace orogen::test
