// orogen-editor: the node editor.
//
//   orogen-editor [FILE]                       open a graph (or start with an empty one)
//   orogen-editor FILE --screenshot PNG --frames N
//                                              render N frames (and until the preview is evaluated), save
//                                              the window as PNG and exit: for tests and documentation
#include <cstdio>
#include <exception>

#include <CLI/CLI.hpp>

#include "editor/ui/app.h"

int main(int argc, char** argv) {
  orogen::editor::AppOptions options;
  CLI::App cli{"orogen-editor: build and tune Orogen terrain graphs with live 2D and 3D preview"};
  cli.add_option("file", options.file, "Graph file to open")->check(CLI::ExistingFile);
  cli.add_option("--screenshot", options.screenshot, "Save the window as this PNG after the frames, then exit");
  cli.add_option("--frames", options.frames, "Frames to render before the screenshot")->check(CLI::Range(1, 100000));
  auto* width = cli.add_option("--size", options.width, "Window width in pixels (height follows 16:9 unless --height)")
                    ->check(CLI::Range(320, 8192));
  auto* height = cli.add_option("--height", options.height, "Window height in pixels")->check(CLI::Range(240, 8192));
  cli.add_option("--select", options.select, "Select this node at start (its parameters and preview are shown)");
  cli.add_flag("!--no-thumbnails", options.thumbnails, "Nodes without thumbnails of their outputs");
  cli.add_option("--port", options.port, "With --select: the output shown in the preview (default: the first)");
  cli.add_option("--channel", options.channel,
                 "With --select: the image channel (by name, e.g. jun) shown in the 2D preview");
  cli.add_option("--color-map", options.color_map,
                 "2D preview color map at start (gray, terrain, viridis, diverging, water, categorical)")
      ->check(CLI::IsMember({"gray", "terrain", "viridis", "diverging", "water", "categorical"}));
  cli.add_option("--view", options.view, "Preview panel at start")->check(CLI::IsMember({"2d", "3d"}));
  cli.add_option("--drape", options.drape, "Image node draped over the 3D terrain at start");
  cli.add_option("--camera", options.camera,
                 "3D view at start: YAW PITCH ZOOM (degrees around +z, 0 looks along +y; degrees above the horizon; "
                 "wheel notches after framing, > 0 closer)")
      ->expected(3)
      ->delimiter(',');
  cli.add_option("--preview-width", options.preview_width,
                 "Width of the preview and inspector column at start (pixels)")
      ->check(CLI::Range(260.0f, 8192.0f));
  cli.add_option("--preview-resolution", options.preview_resolution,
                 "Preview samples along the longer side (default 512)")
      ->check(CLI::Range(16, 8192));
  cli.add_option("--state-dir", options.state_dir,
                 "Where recent files and crash-recovery files live (default $XDG_STATE_HOME/orogen)");
  cli.add_option("--output-dir", options.output_dir, "Where builds write their files (default out/)");
  cli.add_flag("--benchmark-build", options.benchmark_build,
               "Start a build at once, print the frame times while it runs, exit when it is done");
  cli.add_option("--build-resolution", options.build_resolution, "With --benchmark-build: build at N x N samples")
      ->check(CLI::Range(2, 32768));
  cli.add_option("--plugin", options.plugins,
                 "Load a node library (.so built with orogen_add_node_library); repeatable. Libraries of "
                 "OROGEN_PLUGIN_PATH and of Help > Node Libraries load too");
  cli.add_option("--group", options.group,
                 "Group these nodes into a subgraph at start, as Ctrl+G does (screenshots; writes the asset beside "
                 "the file)")
      ->delimiter(',');
  cli.add_option("--enter", options.enter, "Enter this subgraph instance at start, as Tab does (screenshots)");
  cli.add_option("--palette", options.palette_query, "Open the node palette with this search typed (screenshots)");
  cli.add_flag("--offer-recovery", options.offer_recovery_in_screenshot,
               "With --screenshot: still offer crash-recovery files (screenshots of the prompt)");
  CLI11_PARSE(cli, argc, argv);
  if (width->count() && !height->count()) options.height = options.width * 9 / 16;
  try {
    orogen::editor::App app(std::move(options));
    return app.run();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "orogen-editor: %s\n", e.what());
    return 1;
  }
}
