#pragma once
// The editor application: the window, the panels (node canvas, 2D/3D preview, inspector, status bar), the
// menus, file handling with unsaved-changes prompts, autosave and crash recovery, recent files and
// examples, background preview and build.
#include <chrono>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "editor/model/canvas_controller.h"
#include "editor/model/document.h"
#include "editor/model/evaluation_controller.h"
#include "editor/model/frame_pacing.h"
#include "editor/model/input_queue.h"
#include "editor/model/node_library_preferences.h"
#include "editor/model/recent_files.h"
#include "editor/model/recovery.h"
#include "editor/model/selection.h"
#include "editor/model/subgraph_navigation.h"
#include "editor/ui/file_dialog.h"
#include "editor/ui/inspector.h"
#include "editor/ui/node_canvas.h"
#include "editor/ui/preview_2d.h"
#include "editor/ui/preview_panel.h"
#include "editor/ui/viewport_3d.h"

struct GLFWwindow;
struct ImFont;

namespace orogen::editor {

struct AppOptions {
  std::filesystem::path file;        // opened at start
  std::filesystem::path screenshot;  // save the window as PNG after `frames` frames and exit
  int frames = 60;
  int width = 1600, height = 900;
  std::string select;                  // node selected at start (documentation screenshots)
  std::string port;                    // its output shown in the preview
  std::string channel;                 // image channel shown as a field in the 2D preview (name), "" composite
  std::string color_map;               // 2D preview colour map at start (kColorMapNames), "" automatic
  bool thumbnails = true;              // node thumbnails on the canvas
  std::string view = "2d";             // preview panel at start: 2d or 3d
  std::string drape;                   // Image node draped over the 3D terrain at start
  std::vector<double> camera;          // 3D view at start: yaw, pitch (degrees), zoom (wheel notches after framing)
  float preview_width = 0.0f;          // width of the preview / inspector column at start (pixels); 0: default
  std::filesystem::path state_dir;     // recent files and recovery; default_state_dir() if empty
  std::filesystem::path examples_dir;  // graphs/ of the installation; searched if empty
  int preview_resolution = EvaluationController::kDefaultPreviewResolution;
  std::filesystem::path output_dir = "out";  // where builds write
  // Measurement: start a build at once (at `build_resolution` if set), print the frame times while it runs,
  // and exit when it is done.
  bool benchmark_build = false;
  std::string palette_query;
  std::vector<std::string> group;  // documentation screenshots: group these nodes at start (Ctrl+G)
  std::string enter;               // documentation screenshots: enter this subgraph instance at start
  std::vector<std::string>
      plugins;  // node libraries to load at start, besides the preferences' and OROGEN_PLUGIN_PATH's
  bool offer_recovery_in_screenshot = false;  // screenshots normally skip the crash-recovery prompt  // documentation
                                              // screenshots: open the node palette with this query typed
  int build_resolution = 0;
};

class App {
 public:
  explicit App(AppOptions options);
  ~App();
  App(const App&) = delete;
  App& operator=(const App&) = delete;

  // Runs until the user quits (or the screenshot is taken). Returns the process exit code.
  int run();

 private:
  // Frame.
  void frame();
  void install_input_callbacks();
  void feed_queued_input();       // after the backend's NewFrame: this frame's share of the queued events
  bool animating() const;         // something changes on screen without input
  LoopState loop_state() const;   // what decides when the next frame is drawn (model/frame_pacing.h)
  bool thumbnails_shown() const;  // the canvas shows thumbnails of the current content (or none are wanted)
  void draw_menu_bar();
  void draw_panels();
  void draw_status_bar(float height);
  void draw_modals();
  void handle_shortcuts();

  // Documents.
  void set_document(std::unique_ptr<Document> document);
  void open_file(const std::filesystem::path& path);
  bool save();  // false if it needs Save As first or failed
  void save_as(const std::filesystem::path& path);
  // Runs `action` now, or after asking what to do with unsaved changes.
  void guard_unsaved(std::function<void()> action);
  void request_quit();
  std::vector<std::filesystem::path> examples() const;

  // Preview.
  std::string preview_node() const;
  std::vector<std::string> preview_request(const std::string& node) const;
  void update_preview();
  PreviewContent preview_content(const std::string& node) const;
  PreviewContent scene_content(const std::string& node, const SceneSources& sources) const;
  ImagePtr drape_image(const PreviewResult& result) const;

  // Build.
  void start_build();
  glm::ivec2 build_samples() const;  // the resolution Build > Resolution chose (the file's by default)

  void show_error(std::string text) { error_text_ = std::move(text); }

  AppOptions options_;
  GLFWwindow* window_ = nullptr;
  ImFont* canvas_font_ = nullptr;

  std::unique_ptr<Document> document_;  // the root: the file opened
  // The subgraph levels entered (editor/model/subgraph_navigation.h); the canvas, preview and inspector work
  // on its current level, saving and building on the root.
  std::unique_ptr<SubgraphNavigator> navigator_;
  Document& doc() { return navigator_->current(); }
  const Document& doc() const { return navigator_->current(); }
  const Document* shown_level_ = nullptr;  // the level the preview state belongs to
  void level_changed();
  // What previews evaluate: the root graph (in the entered instance's context, EvaluationController::
  // set_context), and the revision that tags its results.
  const Graph& preview_graph() const { return document_->graph(); }
  std::uint64_t preview_revision() const { return document_->content_revision(); }
  // What output `port` of a node of the current level holds (resolve_output_kind); inside an instance, through
  // its inputs in the expanded root graph, kept per root revision.
  OutputKind output_kind(const std::string& node, const std::string& port) const;
  mutable std::optional<Graph> kind_graph_;
  mutable std::uint64_t kind_graph_revision_ = ~std::uint64_t(0);
  void draw_breadcrumbs();
  std::filesystem::path open_asset_;  // the inspector's "Open asset", done after the frame's drawing
  Selection selection_;
  EvaluationController evaluation_;
  std::unique_ptr<CanvasController> canvas_;
  std::unique_ptr<NodeCanvasView> canvas_view_;
  Inspector inspector_;
  Preview2D preview_2d_;
  std::unique_ptr<Viewport3D> viewport_3d_;

  std::filesystem::path state_dir_;
  RecoveryStore recovery_;
  Autosaver autosaver_;
  RecentFiles recent_;
  NodeLibraryPreferences node_libraries_;
  std::vector<std::string> node_library_errors_;  // libraries that failed to load, shown in their window
  std::string node_library_entry_;                // the path typed in the Node Libraries window
  bool show_node_libraries_ = false;
  std::vector<RecoveryFile> recovery_offer_;

  FileDialog file_dialog_;
  enum class FileAction { None, Open, SaveAs, SaveAsThen, GroupTo } file_action_ = FileAction::None;
  std::function<void()> after_save_;      // continuation of Save As from the unsaved-changes prompt
  std::function<void()> pending_action_;  // waiting for the unsaved-changes prompt
  bool prompt_unsaved_ = false;
  bool show_shortcuts_ = false, show_about_ = false;
  void draw_node_libraries_window();
  std::string error_text_;

  // Preview state.
  std::string pinned_;                     // preview pinned to this node (double-click on a node)
  std::map<std::string, int> shown_port_;  // output shown per node
  std::string drape_node_;                 // an Image node draped over the 3D terrain
  std::uint64_t requested_revision_ = ~std::uint64_t(0);
  std::vector<std::string> requested_nodes_;
  int requested_resolution_ = 0;
  std::chrono::steady_clock::time_point last_request_{};
  bool pending_request_ = false;
  std::uint64_t thumbnails_revision_ = 0;  // content revision + 1 of the last thumbnail request
  bool show_3d_ = false;
  bool frame_canvas_ = true;

  // Layout.
  float right_width_ = 0.0f;
  float preview_fraction_ = 0.56f;

  std::filesystem::path output_dir_ = "out";
  std::string build_choice_;  // BuildResolution::name chosen in Build > Resolution ("" the file's)
  std::string title_;
  bool quit_ = false;
  int frame_count_ = 0;

  // Input queued by the GLFW callbacks, released a frame at a time (see input_queue.h).
  InputQueue input_queue_;
  InputFrame input_state_;
  int redraw_frames_ = 3;  // frames still to draw before waiting for events
  bool was_busy_ = false;  // a preview or build ran at the previous frame
  std::chrono::steady_clock::time_point last_input_{};
  std::chrono::steady_clock::time_point last_frame_drawn_{};  // when the last frame started
};

}  // namespace orogen::editor
