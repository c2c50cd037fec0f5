#include "editor/ui/app.h"

#include <algorithm>
#include <cfloat>
#include <cstdio>
#include <thread>
#include <utility>

#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>
#include <imgui_stdlib.h>

#include "editor/model/asset_palette.h"
#include "editor/model/build_resolutions.h"
#include "editor/model/grouping.h"
#include "editor/model/node_layout.h"
#include "editor/model/preview_image.h"
#include "editor/model/state_dir.h"
#include "graph/node_library.h"
#include "editor/ui/frame_timing.h"
#include "editor/ui/gl.h"
#include "editor/ui/screenshot.h"
#include "editor/ui/theme.h"
#include "graph/graph_file.h"
#include "graph/registry.h"
#include "graph/subgraph.h"

namespace orogen::editor {

namespace {

constexpr float kStatusBarHeight = 26.0f;
constexpr auto kRequestThrottle = std::chrono::milliseconds(120);  // between superseding previews while busy

std::filesystem::path resolve_state_dir(const AppOptions& o) {
  return o.state_dir.empty() ? default_state_dir() : o.state_dir;
}

void glfw_error(int code, const char* text) { std::fprintf(stderr, "orogen-editor: GLFW error %d: %s\n", code, text); }

// Splitter between panels; returns the drag delta along its axis.
float splitter(const char* id, bool vertical, float thickness, float length) {
  ImGui::InvisibleButton(id, vertical ? ImVec2(thickness, length) : ImVec2(length, thickness));
  const bool active = ImGui::IsItemActive();
  if (ImGui::IsItemHovered() || active)
    ImGui::SetMouseCursor(vertical ? ImGuiMouseCursor_ResizeEW : ImGuiMouseCursor_ResizeNS);
  const ImVec2 a = ImGui::GetItemRectMin(), b = ImGui::GetItemRectMax();
  ImGui::GetWindowDrawList()->AddRectFilled(a, b, active ? IM_COL32(255, 176, 60, 200) : IM_COL32(40, 43, 48, 255));
  return active ? (vertical ? ImGui::GetIO().MouseDelta.x : ImGui::GetIO().MouseDelta.y) : 0.0f;
}

std::string format_duration(double ms) {
  char buf[32];
  if (ms < 1000.0)
    std::snprintf(buf, sizeof buf, "%.0f ms", ms);
  else
    std::snprintf(buf, sizeof buf, "%.1f s", ms / 1000.0);
  return buf;
}

// A build leaves out nodes not wired yet that no output needs: said, not failed.
std::string left_out_note(const std::vector<std::string>& ids) {
  if (ids.empty()) return "";
  std::string note = " (left out, not wired: ";
  for (std::size_t k = 0; k < ids.size() && k < 3; ++k) note += (k ? ", " : "") + ids[k];
  return note + (ids.size() > 3 ? ", ...)" : ")");
}

}  // namespace

App::App(AppOptions options)
    : options_(std::move(options)),
      document_(std::make_unique<Document>()),
      inspector_(evaluation_),
      state_dir_(resolve_state_dir(options_)),
      recovery_(state_dir_ / "recovery"),
      autosaver_(recovery_),
      recent_(state_dir_ / "recent.json"),
      node_libraries_(state_dir_ / "node_libraries.json") {
  // Before any graph is opened, so that its nodes of library types are found.
  node_library_errors_ = load_editor_node_libraries(node_libraries_, options_.plugins);
  show_node_libraries_ = !node_library_errors_.empty();
  glfwSetErrorCallback(glfw_error);
  if (!glfwInit()) throw std::runtime_error("cannot initialize GLFW (is there a display?)");
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  window_ = glfwCreateWindow(options_.width, options_.height, "Orogen", nullptr, nullptr);
  if (!window_) {
    glfwTerminate();
    throw std::runtime_error("cannot open an OpenGL 3.3 window");
  }
  glfwMakeContextCurrent(window_);
  glfwSwapInterval(options_.screenshot.empty() ? 1 : 0);

  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGuiIO& io = ImGui::GetIO();
  io.IniFilename = nullptr;  // the layout is ours; nothing to persist in the working directory
  // A steady caret: a blinking one would need a frame every half second while a text field has the focus.
  io.ConfigInputTextCursorBlink = false;
  theme::apply_style();
  // DejaVu Sans when installed (fonts-dejavu-core), ImGui's built-in font otherwise. The canvas gets a
  // larger bake of the same font so zoomed-in node text stays sharp.
  const char* kFont = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
  if (std::filesystem::exists(kFont)) {
    io.Fonts->AddFontFromFileTTF(kFont, 15.0f);
    canvas_font_ = io.Fonts->AddFontFromFileTTF(kFont, 28.0f);
  } else {
    io.Fonts->AddFontDefault();
  }
  // Our callbacks queue the input (see input_queue.h); the backend gets focus, enter and monitor events.
  ImGui_ImplGlfw_InitForOpenGL(window_, false);
  install_input_callbacks();
  ImGui_ImplOpenGL3_Init("#version 330 core");

  // A finished preview or build wakes the loop from waiting for events.
  evaluation_.set_on_change([] { glfwPostEmptyEvent(); });
  evaluation_.set_preview_resolution(options_.preview_resolution);
  output_dir_ = options_.output_dir;
  navigator_ = std::make_unique<SubgraphNavigator>(*document_);
  std::vector<std::string> library_errors;
  auto palette_types = palette_types_with_library(&library_errors);
  for (const auto& e : library_errors) std::fprintf(stderr, "orogen-editor: %s\n", e.c_str());
  canvas_ = std::make_unique<CanvasController>(
      *document_, selection_,
      ClipboardAccess{[] {
                        const char* t = ImGui::GetClipboardText();
                        return std::string(t ? t : "");
                      },
                      [](const std::string& s) { ImGui::SetClipboardText(s.c_str()); }},
      std::move(palette_types));
  canvas_->set_navigator(navigator_.get());
  inspector_.set_subgraph_actions(
      [this](const std::string& id) { canvas_->enter_subgraph(id); },
      // Opened after the frame's drawing: the inspector is still drawing the node of the document it replaces.
      [this](const std::filesystem::path& file) { open_asset_ = file; },
      [this](const std::string& id) { navigator_->make_unique(id); });
  canvas_view_ = std::make_unique<NodeCanvasView>(*canvas_, evaluation_);
  canvas_view_->set_output_kind(
      [this](const std::string& node, const std::string& port) { return output_kind(node, port); });
  canvas_->set_thumbnails(options_.thumbnails);
  viewport_3d_ = std::make_unique<Viewport3D>();
  show_3d_ = options_.view == "3d";
  drape_node_ = options_.drape;
  if (options_.camera.size() == 3) viewport_3d_->set_view(options_.camera[0], options_.camera[1], options_.camera[2]);
  right_width_ = options_.preview_width;
  preview_2d_.set_start(options_.channel, options_.color_map);

  if (!options_.file.empty()) open_file(options_.file);
  if (!options_.group.empty()) {
    selection_.set(options_.group);
    canvas_->group_selection();
    if (!canvas_->message().empty()) std::fprintf(stderr, "orogen-editor: %s\n", canvas_->message().c_str());
  }
  if (!options_.enter.empty() && !canvas_->enter_subgraph(options_.enter))
    std::fprintf(stderr, "orogen-editor: %s\n", canvas_->message().c_str());
  if (!doc().graph().find(options_.drape))
    drape_node_.clear();
  else
    drape_node_ = options_.drape;
  if (!options_.select.empty() && doc().graph().find(options_.select)) {
    selection_.select_only(options_.select);
    if (const int k = doc().graph().at(options_.select).type->output_index(options_.port); k >= 0)
      shown_port_[options_.select] = k;
  }
  // A screenshot run is not a session: it never offers (or takes) someone's recovery files.
  if (options_.screenshot.empty() || options_.offer_recovery_in_screenshot) recovery_offer_ = recovery_.orphans();
}

App::~App() {
  evaluation_.set_on_change({});  // no wake-ups once GLFW is gone
  // GL objects go while the context exists.
  viewport_3d_.reset();
  preview_2d_ = Preview2D();
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  glfwDestroyWindow(window_);
  glfwTerminate();
}

int App::run() {
  using clock = std::chrono::steady_clock;
  const bool screenshot = !options_.screenshot.empty();
  const auto deadline = clock::now() + std::chrono::seconds(180);
  // Screenshots show the UI, not whatever tooltip the pointer's resting place would open.
  if (screenshot) glfwSetCursorPos(window_, 1.0, options_.height - 2.0);
  int settle = -1;     // frames left before the screenshot once everything is evaluated
  FrameTiming timing;  // --benchmark-build
  double work_ms = 0.0, cpu_ms = 0.0, raster_ms = 0.0;
  bool build_started = false;
  auto last_frame = clock::now();
  while (!quit_) {
    const auto frame_start = clock::now();
    const double interval_ms = std::chrono::duration<double, std::milli>(frame_start - last_frame).count();
    last_frame = frame_start;
    if (options_.benchmark_build && !build_started && !evaluation_.preview_busy() && frame_count_ >= 10) {
      timing.record(false, interval_ms, work_ms, cpu_ms, raster_ms);
      if (timing.idle_frames() >= 60) {
        Graph g = document_->graph();
        if (options_.build_resolution > 0) g.domain.resolution = {options_.build_resolution, options_.build_resolution};
        OutputPolicy policy;
        policy.output_dir = output_dir_;
        evaluation_.start_build(g, policy);
        build_started = true;
      }
    } else if (build_started) {
      const auto status = evaluation_.build_status();
      if (status.running) {
        timing.record(true, interval_ms, work_ms, cpu_ms, raster_ms);
      } else {
        timing.print(status, reinterpret_cast<const char*>(glGetString(GL_RENDERER)));
        quit_ = true;
        break;
      }
    }
    // Nothing changing and no input pending: block until an event (input, or a finished evaluation posting an
    // empty event); a timer only for what changes by itself (model/frame_pacing.h).
    const bool busy = animating();
    if (was_busy_ && !busy) redraw_frames_ = 3;  // a few frames after it ends, so the final state is drawn
    was_busy_ = busy;
    if (screenshot || options_.benchmark_build) {
      glfwPollEvents();
    } else {
      const FrameWait wait = next_frame_wait(loop_state());
      if (wait.mode == FrameWait::Mode::Draw) {
        glfwPollEvents();
      } else {
        if (wait.mode == FrameWait::Mode::WaitForever)
          glfwWaitEvents();
        else
          glfwWaitEventsTimeout(wait.seconds);
      }
    }
    if (!input_queue_.empty()) redraw_frames_ = 3;
    if (redraw_frames_ > 0) --redraw_frames_;
    if (glfwWindowShouldClose(window_)) {
      glfwSetWindowShouldClose(window_, GLFW_FALSE);
      request_quit();
    }
    if (!options_.palette_query.empty() && frame_count_ == 5) {
      canvas_->open_palette(canvas_->view().viewport().center() - glm::dvec2(160.0, 180.0));
      canvas_->palette().set_query(options_.palette_query);
    }
    const auto work_start = clock::now();
    last_frame_drawn_ = work_start;
    const double cpu_start = FrameTiming::thread_cpu_ms();
    frame();
    work_ms = std::chrono::duration<double, std::milli>(clock::now() - work_start).count();
    cpu_ms = FrameTiming::thread_cpu_ms() - cpu_start;
    if (options_.benchmark_build) {
      // Separates the rasterisation (done by the CPU with software OpenGL) from the UI thread's own work.
      const auto raster_start = clock::now();
      glFinish();
      raster_ms = std::chrono::duration<double, std::milli>(clock::now() - raster_start).count();
    }
    ++frame_count_;
    if (screenshot) {
      if (settle < 0 && frame_count_ >= options_.frames &&
          ((!evaluation_.preview_busy() && !pending_request_ && thumbnails_shown()) || clock::now() > deadline))
        settle = 3;  // a few frames more so the last result is uploaded and drawn
      if (settle == 0) {
        int w = 0, h = 0;
        glfwGetFramebufferSize(window_, &w, &h);
        save_framebuffer_png(options_.screenshot, w, h);
        quit_ = true;
      }
      if (settle > 0) --settle;
    }
    glfwSwapBuffers(window_);
  }
  recovery_.discard();  // a clean exit leaves nothing to recover
  return 0;
}

namespace {
App* app_of(GLFWwindow* w) { return static_cast<App*>(glfwGetWindowUserPointer(w)); }
}  // namespace

void App::install_input_callbacks() {
  glfwSetWindowUserPointer(window_, this);
  glfwSetKeyCallback(window_, [](GLFWwindow* w, int key, int, int action, int) {
    if (action != GLFW_REPEAT) app_of(w)->input_queue_.push({RawInput::Kind::Key, key, action == GLFW_PRESS, {}});
  });
  glfwSetMouseButtonCallback(window_, [](GLFWwindow* w, int button, int action, int) {
    app_of(w)->input_queue_.push({RawInput::Kind::Button, button, action == GLFW_PRESS, {}});
  });
  glfwSetCursorPosCallback(window_, [](GLFWwindow* w, double x, double y) {
    app_of(w)->input_queue_.push({RawInput::Kind::Move, 0, false, {x, y}});
  });
  glfwSetScrollCallback(window_, [](GLFWwindow* w, double x, double y) {
    app_of(w)->input_queue_.push({RawInput::Kind::Scroll, 0, false, {x, y}});
  });
  glfwSetCharCallback(window_, [](GLFWwindow* w, unsigned c) {
    app_of(w)->input_queue_.push({RawInput::Kind::Char, static_cast<int>(c), false, {}});
  });
  glfwSetWindowFocusCallback(window_, [](GLFWwindow* w, int focused) {
    ImGui_ImplGlfw_WindowFocusCallback(w, focused);
    // Releases happen elsewhere while unfocused: nothing stays held.
    if (!focused) app_of(w)->input_queue_.release_all();
  });
  glfwSetCursorEnterCallback(window_, ImGui_ImplGlfw_CursorEnterCallback);
  glfwSetMonitorCallback(ImGui_ImplGlfw_MonitorCallback);
  // Resizing and exposing redraw.
  glfwSetWindowRefreshCallback(window_, [](GLFWwindow* w) { app_of(w)->redraw_frames_ = 3; });
  glfwSetFramebufferSizeCallback(window_, [](GLFWwindow* w, int, int) { app_of(w)->redraw_frames_ = 3; });
}

void App::feed_queued_input() {
  ImGuiIO& io = ImGui::GetIO();
  // WantTextInput is last frame's: whether a text field has the keyboard now.
  if (input_queue_.next_frame(input_state_, io.WantTextInput) > 0) last_input_ = std::chrono::steady_clock::now();
  const InputFrame& in = input_state_;
  for (int k = 0; k < InputFrame::kKeys && k < IM_ARRAYSIZE(io.KeysDown); ++k)
    io.KeysDown[k] = in.keys[static_cast<std::size_t>(k)];
  io.KeyCtrl = in.keys[GLFW_KEY_LEFT_CONTROL] || in.keys[GLFW_KEY_RIGHT_CONTROL];
  io.KeyShift = in.keys[GLFW_KEY_LEFT_SHIFT] || in.keys[GLFW_KEY_RIGHT_SHIFT];
  io.KeyAlt = in.keys[GLFW_KEY_LEFT_ALT] || in.keys[GLFW_KEY_RIGHT_ALT];
  io.KeySuper = in.keys[GLFW_KEY_LEFT_SUPER] || in.keys[GLFW_KEY_RIGHT_SUPER];
  for (int b = 0; b < InputFrame::kButtons && b < IM_ARRAYSIZE(io.MouseDown); ++b)
    io.MouseDown[b] = in.buttons[static_cast<std::size_t>(b)];
  // The backend polled the pointer; the queued position is where the released events happened (unless the
  // pointer is outside an unfocused window, where the backend reports none).
  if (in.has_pointer && io.MousePos.x > -FLT_MAX)
    io.MousePos = ImVec2(static_cast<float>(in.pointer.x), static_cast<float>(in.pointer.y));
  // A screenshot shows no hover: wherever the display's pointer rests (Xvfb: its center, over a node now that
  // files open at a readable zoom), it opens no tooltip.
  if (!options_.screenshot.empty()) io.MousePos = ImVec2(-FLT_MAX, -FLT_MAX);
  io.MouseWheelH += static_cast<float>(in.wheel.x);
  io.MouseWheel += static_cast<float>(in.wheel.y);
  for (unsigned c : in.chars) io.AddInputCharacter(c);
}

bool App::thumbnails_shown() const {
  if (!canvas_->thumbnails()) return true;
  const auto t = evaluation_.thumbnails();
  return t && t->revision == preview_revision() && thumbnails_revision_ == preview_revision() + 1;
}

bool App::animating() const {
  return evaluation_.preview_busy() || evaluation_.build_status().running || pending_request_;
}

LoopState App::loop_state() const {
  LoopState s;
  s.now = std::chrono::steady_clock::now();
  s.input_pending = !input_queue_.empty();
  s.redraw_frames = redraw_frames_;
  s.busy = animating();
  // Modifiers held alone change nothing on screen; other keys repeat, buttons drag.
  s.held = std::any_of(input_state_.buttons.begin(), input_state_.buttons.end(), [](bool b) { return b; });
  for (int k = 0; k < InputFrame::kKeys && !s.held; ++k)
    s.held = input_state_.keys[static_cast<std::size_t>(k)] && (k < GLFW_KEY_LEFT_SHIFT || k > GLFW_KEY_RIGHT_SUPER);
  if (last_input_ != std::chrono::steady_clock::time_point{}) s.last_input = last_input_;
  if (last_frame_drawn_ != std::chrono::steady_clock::time_point{}) s.last_frame = last_frame_drawn_;
  s.autosave_due = autosaver_.next_due(*document_);
  return s;
}

void App::frame() {
  ImGui_ImplOpenGL3_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  feed_queued_input();
  ImGui::NewFrame();

  handle_shortcuts();
  const ImGuiViewport* vp = ImGui::GetMainViewport();
  ImGui::SetNextWindowPos(vp->WorkPos);
  ImGui::SetNextWindowSize(vp->WorkSize);
  ImGui::PushStyleVar(ImGuiStyleVar_WindowPadding, {0, 0});
  ImGui::Begin("##main", nullptr,
               ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoSavedSettings |
                   ImGuiWindowFlags_MenuBar | ImGuiWindowFlags_NoBringToFrontOnFocus | ImGuiWindowFlags_NoBackground);
  ImGui::PopStyleVar();
  draw_menu_bar();
  draw_panels();
  ImGui::End();
  draw_modals();

  if (!open_asset_.empty()) guard_unsaved([this, file = std::exchange(open_asset_, {})] { open_file(file); });
  // Edits inside a subgraph go to its asset file, and every instance above follows.
  if (navigator_->inside()) navigator_->sync();
  if (&doc() != shown_level_) level_changed();
  update_preview();
  autosaver_.tick(*document_, std::chrono::steady_clock::now());
  const std::string title = document_->window_title();
  if (title != title_) {
    glfwSetWindowTitle(window_, title.c_str());
    title_ = title;
  }

  ImGui::Render();
  int w = 0, h = 0;
  glfwGetFramebufferSize(window_, &w, &h);
  glViewport(0, 0, w, h);
  glClearColor(0.13f, 0.14f, 0.16f, 1.0f);  // the window background colour of the theme
  glClear(GL_COLOR_BUFFER_BIT);
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
}

void App::handle_shortcuts() {
  ImGuiIO& io = ImGui::GetIO();
  if (io.WantTextInput || !io.KeyCtrl) return;
  const bool shift = io.KeyShift;
  if (ImGui::IsKeyPressed(GLFW_KEY_Z, false)) shift ? canvas_->redo() : canvas_->undo();
  if (ImGui::IsKeyPressed(GLFW_KEY_Y, false)) canvas_->redo();
  if (ImGui::IsKeyPressed(GLFW_KEY_S, false)) {
    if (shift || !document_->has_path()) {
      file_action_ = FileAction::SaveAs;
      file_dialog_.show(FileDialog::Mode::Save, "Save As", document_->path(), {".json"});
    } else {
      save();
    }
  }
  if (ImGui::IsKeyPressed(GLFW_KEY_O, false))
    guard_unsaved([this] {
      file_action_ = FileAction::Open;
      file_dialog_.show(FileDialog::Mode::Open, "Open", document_->path(), {".json"});
    });
  if (ImGui::IsKeyPressed(GLFW_KEY_N, false)) guard_unsaved([this] { set_document(std::make_unique<Document>()); });
  if (ImGui::IsKeyPressed(GLFW_KEY_Q, false)) request_quit();
  if (ImGui::IsKeyPressed(GLFW_KEY_B, false)) start_build();
}

void App::draw_menu_bar() {
  if (!ImGui::BeginMenuBar()) return;
  if (ImGui::BeginMenu("File")) {
    if (ImGui::MenuItem("New", "Ctrl+N")) guard_unsaved([this] { set_document(std::make_unique<Document>()); });
    if (ImGui::MenuItem("Open...", "Ctrl+O"))
      guard_unsaved([this] {
        file_action_ = FileAction::Open;
        file_dialog_.show(FileDialog::Mode::Open, "Open", document_->path(), {".json"});
      });
    if (ImGui::BeginMenu("Open Recent", !recent_.paths().empty())) {
      for (const auto& p : recent_.paths())
        if (ImGui::MenuItem(p.filename().string().c_str()))
          guard_unsaved([this, p] { open_file(p); });
        else if (ImGui::IsItemHovered())
          ImGui::SetTooltip("%s", p.string().c_str());
      ImGui::Separator();
      if (ImGui::MenuItem("Clear list")) recent_.clear();
      ImGui::EndMenu();
    }
    const auto ex = examples();
    if (ImGui::BeginMenu("Examples", !ex.empty())) {
      for (const auto& p : ex)
        if (ImGui::MenuItem(p.stem().string().c_str())) guard_unsaved([this, p] { open_file(p); });
      ImGui::EndMenu();
    }
    ImGui::Separator();
    if (ImGui::MenuItem("Save", "Ctrl+S")) {
      if (!save()) {
        file_action_ = FileAction::SaveAs;
        file_dialog_.show(FileDialog::Mode::Save, "Save As", document_->path(), {".json"});
      }
    }
    if (ImGui::MenuItem("Save As...", "Ctrl+Shift+S")) {
      file_action_ = FileAction::SaveAs;
      file_dialog_.show(FileDialog::Mode::Save, "Save As", document_->path(), {".json"});
    }
    ImGui::Separator();
    if (ImGui::MenuItem("Quit", "Ctrl+Q")) request_quit();
    ImGui::EndMenu();
  }
  if (ImGui::BeginMenu("Edit")) {
    const auto& h = doc().history();
    if (ImGui::MenuItem(h.can_undo() ? ("Undo " + h.undo_label()).c_str() : "Undo", "Ctrl+Z", false, h.can_undo()))
      canvas_->undo();
    if (ImGui::MenuItem(h.can_redo() ? ("Redo " + h.redo_label()).c_str() : "Redo", "Ctrl+Shift+Z", false,
                        h.can_redo()))
      canvas_->redo();
    ImGui::Separator();
    const bool any = !selection_.empty();
    if (ImGui::MenuItem("Copy", "Ctrl+C", false, any)) canvas_->copy_selection();
    if (ImGui::MenuItem("Paste", "Ctrl+V")) canvas_->paste();
    if (ImGui::MenuItem("Duplicate", "Ctrl+D", false, any)) canvas_->duplicate_selection();
    if (ImGui::MenuItem("Delete", "Del / X", false, any)) canvas_->delete_selection();
    ImGui::Separator();
    if (ImGui::MenuItem("Select All", "Ctrl+A")) canvas_->select_all();
    ImGui::Separator();
    bool instance_selected = false;
    for (const auto& id : selection_.ids())
      if (const Node* n = doc().graph().find(id); n && n->type->subgraph) instance_selected = true;
    if (ImGui::MenuItem("Group into Subgraph", "Ctrl+G", false, any)) canvas_->group_selection();
    if (ImGui::MenuItem("Group into Subgraph File...", nullptr, false, any)) {
      file_action_ = FileAction::GroupTo;
      file_dialog_.show(FileDialog::Mode::Save, "Group into Subgraph File", free_asset_path(document_directory(doc())),
                        {".json"});
    }
    if (ImGui::MenuItem("Ungroup", "Ctrl+Shift+G", false, instance_selected)) canvas_->ungroup_selection();
    if (ImGui::MenuItem("Enter Subgraph", "Tab", false, instance_selected && selection_.size() == 1))
      canvas_->enter_subgraph();
    if (ImGui::MenuItem("Leave Subgraph", "Shift+Tab", false, navigator_->inside())) canvas_->leave_subgraph();
    if (ImGui::MenuItem("Add Node...", "Tab")) canvas_->open_palette(canvas_->view().viewport().center());
    ImGui::EndMenu();
  }
  if (ImGui::BeginMenu("View")) {
    if (ImGui::MenuItem("Frame All", "Home")) canvas_->frame(false);
    if (ImGui::MenuItem("Frame Selected", "F", false, !selection_.empty())) canvas_->frame(true);
    ImGui::Separator();
    const bool pinned = !pinned_.empty();
    if (ImGui::MenuItem("Pin Preview to Selected", "double-click", pinned, pinned || !selection_.active().empty()))
      pinned_ = pinned ? std::string() : selection_.active();
    if (ImGui::MenuItem("3D Viewport", nullptr, show_3d_)) show_3d_ = !show_3d_;
    if (ImGui::MenuItem("Node Thumbnails", nullptr, canvas_->thumbnails())) {
      canvas_->set_thumbnails(!canvas_->thumbnails());
      // Nodes grow: move apart those that would overlap (one undoable step).
      if (canvas_->thumbnails()) doc().edit("Make Room for Thumbnails", [](Graph& g) { make_room_for_thumbnails(g); });
    }
    if (ImGui::BeginMenu("Preview Resolution")) {
      for (int r : {128, 256, 512, 1024, 2048})
        if (ImGui::MenuItem((std::to_string(r) + " samples").c_str(), nullptr, evaluation_.preview_resolution() == r))
          evaluation_.set_preview_resolution(r);
      ImGui::EndMenu();
    }
    ImGui::EndMenu();
  }
  if (ImGui::BeginMenu("Build")) {
    const auto status = evaluation_.build_status();
    const auto choices = build_resolutions(document_->graph().domain);
    const glm::ivec2 samples = build_samples();
    const std::string label = "Build at " + std::to_string(samples.x) + " x " + std::to_string(samples.y);
    if (ImGui::MenuItem(label.c_str(), "Ctrl+B", false, !status.running)) start_build();
    // The file's resolution, quick builds and the engines' sizes (those of orogen eval --resolution).
    if (ImGui::BeginMenu("Resolution")) {
      ImGui::TextDisabled("Samples on the graph's world rectangle (the file is not changed)");
      auto kind = BuildResolution::Kind::File;
      for (const auto& c : choices) {
        if (c.kind != kind) {
          kind = c.kind;
          ImGui::Separator();
          ImGui::TextDisabled("%s", kind == BuildResolution::Kind::Quick ? "Quick" : "Game engines");
        }
        const bool chosen = c.kind == BuildResolution::Kind::File ? build_choice_.empty() : build_choice_ == c.name;
        if (ImGui::MenuItem(c.label().c_str(), nullptr, chosen)) build_choice_ = c.name;
      }
      ImGui::EndMenu();
    }
    if (ImGui::MenuItem("Cancel Build", nullptr, false, status.running)) evaluation_.cancel_build();
    ImGui::Separator();
    std::string dir = output_dir_.string();
    ImGui::SetNextItemWidth(240);
    if (ImGui::InputText("Output folder", &dir)) output_dir_ = dir;
    ImGui::EndMenu();
  }
  if (ImGui::BeginMenu("Help")) {
    if (ImGui::MenuItem("Node Libraries...")) show_node_libraries_ = true;
    if (ImGui::MenuItem("Keyboard and Mouse")) show_shortcuts_ = true;
    if (ImGui::MenuItem("About Orogen")) show_about_ = true;
    ImGui::EndMenu();
  }
  ImGui::EndMenuBar();
}

void App::draw_panels() {
  const ImVec2 avail = ImGui::GetContentRegionAvail();
  const float splitter_w = 5.0f;
  if (right_width_ <= 0.0f) right_width_ = std::clamp(avail.x * 0.36f, 360.0f, 640.0f);
  right_width_ = std::clamp(right_width_, 260.0f, std::max(260.0f, avail.x - 300.0f));
  const float body_h = avail.y - kStatusBarHeight;

  // Node canvas. It paints its own background; the panels under it paint none (every full-screen fill
  // costs a frame a lot with software OpenGL).
  ImGui::PushStyleVar(ImGuiStyleVar_WindowPadding, {0, 0});
  ImGui::BeginChild("##canvas-panel", {avail.x - right_width_ - splitter_w, body_h}, false,
                    ImGuiWindowFlags_NoScrollbar | ImGuiWindowFlags_NoScrollWithMouse | ImGuiWindowFlags_NoMove |
                        ImGuiWindowFlags_NoBackground);
  ImGui::PopStyleVar();
  const std::string previewed = preview_node();
  canvas_view_->set_fonts(ImGui::GetIO().Fonts->Fonts[0], canvas_font_);
  canvas_view_->draw(previewed);
  if (frame_canvas_ && canvas_->view().size().x > 60) {
    canvas_->frame_opening();
    frame_canvas_ = false;
  }
  draw_breadcrumbs();
  if (const auto& id = canvas_view_->double_clicked()) {
    // Double-click goes into an instance (as Tab does); on other nodes it pins the preview.
    const Node* n = doc().graph().find(*id);
    if (n && n->type->subgraph)
      canvas_->enter_subgraph(*id);
    else
      pinned_ = pinned_ == *id ? std::string() : *id;
  }
  ImGui::EndChild();

  ImGui::SameLine(0, 0);
  right_width_ -= splitter("##vsplit", true, splitter_w, body_h);
  ImGui::SameLine(0, 0);

  // Right column: preview on top, inspector below.
  ImGui::BeginChild("##right", {right_width_, body_h}, false, ImGuiWindowFlags_NoScrollbar);
  const float preview_h = std::clamp(preview_fraction_ * body_h, 120.0f, body_h - 120.0f);
  ImGui::BeginChild("##preview", {0, preview_h}, false,
                    ImGuiWindowFlags_NoScrollbar | ImGuiWindowFlags_NoScrollWithMouse);
  {
    const PreviewContent content = preview_content(previewed);
    // Header: what is previewed, which output, pinning, 2D/3D.
    ImGui::SetCursorPos({6, 4});
    if (ImGui::RadioButton("2D", !show_3d_)) show_3d_ = false;
    ImGui::SameLine();
    if (ImGui::RadioButton("3D", show_3d_)) show_3d_ = true;
    ImGui::SameLine();
    const Node* node = previewed.empty() ? nullptr : doc().graph().find(previewed);
    if (node) {
      ImGui::TextColored(ImColor(theme::category_color(node->type->category)), "%s", previewed.c_str());
      if (node->type->outputs.size() > 1) {
        ImGui::SameLine();
        int& port = shown_port_[previewed];
        ImGui::SetNextItemWidth(110);
        if (ImGui::BeginCombo("##port", node->type
                                            ->outputs[static_cast<std::size_t>(
                                                std::clamp(port, 0, static_cast<int>(node->type->outputs.size()) - 1))]
                                            .name.c_str())) {
          for (int k = 0; k < static_cast<int>(node->type->outputs.size()); ++k)
            if (ImGui::Selectable(node->type->outputs[static_cast<std::size_t>(k)].name.c_str(), k == port)) port = k;
          ImGui::EndCombo();
        }
      }
      ImGui::SameLine();
      bool pin = pinned_ == previewed;
      if (ImGui::Checkbox("pin", &pin)) pinned_ = pin ? previewed : std::string();
      if (ImGui::IsItemHovered())
        ImGui::SetTooltip("Keep previewing this node whatever is selected (double-click a node)");
    } else {
      ImGui::TextDisabled("no node");
    }
    if (show_3d_) {
      ImGui::SameLine();
      std::vector<std::string> images;
      for (const auto& n : doc().graph().nodes())
        for (const auto& o : n.type->outputs)
          if (o.type == PortType::Image) {
            images.push_back(n.id);
            break;
          }
      ImGui::SetNextItemWidth(130);
      if (ImGui::BeginCombo("##drape", drape_node_.empty() ? "no drape" : drape_node_.c_str())) {
        if (ImGui::Selectable("no drape", drape_node_.empty())) drape_node_.clear();
        for (const auto& id : images)
          if (ImGui::Selectable(id.c_str(), id == drape_node_)) drape_node_ = id;
        ImGui::EndCombo();
      }
      if (ImGui::IsItemHovered()) ImGui::SetTooltip("Colour image draped over the terrain");
    }
    ImGui::SetCursorPosX(6);
    ImGui::BeginGroup();
    if (show_3d_)
      viewport_3d_->draw(content);
    else
      preview_2d_.draw(content);
    ImGui::EndGroup();
  }
  ImGui::EndChild();
  preview_fraction_ += splitter("##hsplit", false, 5.0f, right_width_) / std::max(1.0f, body_h);
  ImGui::BeginChild("##inspector", {0, 0}, false);
  ImGui::SetCursorPos({8, 6});
  ImGui::BeginGroup();
  ImGui::PushItemWidth(-1);
  inspector_.draw(doc(), selection_);
  ImGui::PopItemWidth();
  ImGui::EndGroup();
  ImGui::EndChild();
  ImGui::EndChild();

  draw_status_bar(kStatusBarHeight);
}

void App::draw_status_bar(float height) {
  ImGui::PushStyleColor(ImGuiCol_ChildBg, ImVec4(0.09f, 0.10f, 0.11f, 1.0f));
  ImGui::BeginChild("##status", {0, height}, false, ImGuiWindowFlags_NoScrollbar);
  ImGui::SetCursorPos({8, (height - ImGui::GetTextLineHeight()) * 0.5f});
  const auto build = evaluation_.build_status();
  if (!canvas_->message().empty()) {
    ImGui::TextColored(ImColor(theme::kError), "%s", canvas_->message().c_str());
  } else if (!navigator_->sync_error().empty()) {
    ImGui::TextColored(ImColor(theme::kError), "%s", navigator_->sync_error().c_str());
  } else if (!autosaver_.last_error().empty()) {
    ImGui::TextColored(ImColor(theme::kError), "%s", autosaver_.last_error().c_str());
  } else if (auto p = evaluation_.preview()) {
    std::size_t computed = 0, cached = 0;
    for (const auto& [id, r] : p->reports) {
      if (r.status == NodeStatus::Cached)
        ++cached;
      else if (r.status == NodeStatus::Computed)
        ++computed;
    }
    ImGui::TextDisabled("preview %d x %d: %zu computed, %zu cached in %s%s", p->domain.width(), p->domain.height(),
                        computed, cached, format_duration(p->milliseconds).c_str(),
                        evaluation_.preview_busy() ? "   (updating...)" : "");
    if (!p->error.empty()) {
      ImGui::SameLine();
      ImGui::TextColored(ImColor(theme::kError), "%s", p->error.c_str());
    }
  } else {
    ImGui::TextDisabled("%s", evaluation_.preview_busy() ? "evaluating..." : "ready");
  }
  // Build progress on the right.
  const float right = ImGui::GetWindowWidth() - 8.0f;
  if (build.running) {
    ImGui::SameLine(right - 420.0f);
    ImGui::TextUnformatted("Building");
    ImGui::SameLine();
    char overlay[128];
    std::snprintf(overlay, sizeof overlay, "%.0f%%  %s", build.fraction * 100.0, build.current.c_str());
    ImGui::ProgressBar(static_cast<float>(build.fraction), {260, ImGui::GetTextLineHeight()}, overlay);
    ImGui::SameLine();
    ImGui::SetCursorPosY(ImGui::GetCursorPosY() - 2);
    if (ImGui::SmallButton("Cancel")) evaluation_.cancel_build();
  } else if (build.finished) {
    std::string text =
        build.cancelled ? "build cancelled"
        : build.ok      ? "build at " + std::to_string(build.domain.width()) + " x " +
                         std::to_string(build.domain.height()) + " done in " + format_duration(build.milliseconds) +
                         " -> " + output_dir_.string() + left_out_note(build.left_out)
                   : "build failed: " + (build.failures.empty() ? std::string("?") : build.failures.front());
    const float w = ImGui::CalcTextSize(text.c_str()).x;
    ImGui::SameLine(std::max(200.0f, right - w));
    ImGui::TextColored(build.ok ? ImVec4(0.5f, 0.85f, 0.5f, 1) : ImVec4(0.95f, 0.45f, 0.4f, 1), "%s", text.c_str());
  }
  ImGui::EndChild();
  ImGui::PopStyleColor();
}

void App::draw_modals() {
  if (const auto chosen = file_dialog_.draw()) {
    const auto action = std::exchange(file_action_, FileAction::None);
    if (action == FileAction::Open)
      open_file(*chosen);
    else if (action == FileAction::GroupTo)
      canvas_->group_selection(*chosen);
    else if (action == FileAction::SaveAs || action == FileAction::SaveAsThen) {
      save_as(*chosen);
      if (action == FileAction::SaveAsThen && !document_->dirty() && after_save_) std::exchange(after_save_, nullptr)();
    }
  } else if (!file_dialog_.visible()) {
    file_action_ = FileAction::None;
    after_save_ = nullptr;
  }

  if (prompt_unsaved_) {
    ImGui::OpenPopup("Unsaved changes");
    prompt_unsaved_ = false;
  }
  ImGui::SetNextWindowPos(ImGui::GetMainViewport()->GetCenter(), ImGuiCond_Appearing, {0.5f, 0.5f});
  if (ImGui::BeginPopupModal("Unsaved changes", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
    ImGui::Text("Save the changes to %s?", document_->display_name().c_str());
    ImGui::TextDisabled("Your changes are lost if you don't save them.");
    ImGui::Spacing();
    if (ImGui::Button("Save", {110, 0})) {
      ImGui::CloseCurrentPopup();
      if (save()) {
        std::exchange(pending_action_, nullptr)();
      } else if (!document_->has_path()) {
        after_save_ = std::exchange(pending_action_, nullptr);
        file_action_ = FileAction::SaveAsThen;
        file_dialog_.show(FileDialog::Mode::Save, "Save As", {}, {".json"});
      }
    }
    ImGui::SameLine();
    if (ImGui::Button("Don't Save", {110, 0})) {
      ImGui::CloseCurrentPopup();
      std::exchange(pending_action_, nullptr)();
    }
    ImGui::SameLine();
    if (ImGui::Button("Cancel", {110, 0}) || ImGui::IsKeyPressed(GLFW_KEY_ESCAPE)) {
      ImGui::CloseCurrentPopup();
      pending_action_ = nullptr;
    }
    ImGui::EndPopup();
  }

  if (!recovery_offer_.empty() && !ImGui::IsPopupOpen("Recover unsaved work")) ImGui::OpenPopup("Recover unsaved work");
  ImGui::SetNextWindowPos(ImGui::GetMainViewport()->GetCenter(), ImGuiCond_Appearing, {0.5f, 0.5f});
  if (ImGui::BeginPopupModal("Recover unsaved work", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
    const RecoveryFile& rf = recovery_offer_.front();
    ImGui::TextUnformatted("Orogen was not closed properly last time.");
    ImGui::Text("Unsaved work of %s was autosaved at %s.",
                rf.original.empty() ? "an untitled graph" : rf.original.filename().string().c_str(),
                rf.saved_at.c_str());
    if (!rf.original.empty()) ImGui::TextDisabled("%s", rf.original.string().c_str());
    ImGui::Spacing();
    if (ImGui::Button("Recover", {110, 0})) {
      try {
        auto doc = std::make_unique<Document>(RecoveryStore::load(rf), rf.original);
        doc->mark_unsaved();
        set_document(std::move(doc));
        RecoveryStore::remove(rf);
        autosaver_.flush(*document_);  // the recovered work is now this session's to protect
      } catch (const std::exception& e) {
        show_error(e.what());
      }
      recovery_offer_.erase(recovery_offer_.begin());
      ImGui::CloseCurrentPopup();
    }
    ImGui::SameLine();
    if (ImGui::Button("Discard", {110, 0})) {
      RecoveryStore::remove(rf);
      recovery_offer_.erase(recovery_offer_.begin());
      ImGui::CloseCurrentPopup();
    }
    ImGui::SameLine();
    if (ImGui::Button("Later", {110, 0})) {
      recovery_offer_.clear();  // kept on disk, offered again next time
      ImGui::CloseCurrentPopup();
    }
    ImGui::EndPopup();
  }

  if (!error_text_.empty() && !ImGui::IsPopupOpen("Error")) ImGui::OpenPopup("Error");
  ImGui::SetNextWindowPos(ImGui::GetMainViewport()->GetCenter(), ImGuiCond_Appearing, {0.5f, 0.5f});
  if (ImGui::BeginPopupModal("Error", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
    ImGui::PushTextWrapPos(700);
    ImGui::TextUnformatted(error_text_.c_str());
    ImGui::PopTextWrapPos();
    if (ImGui::Button("OK", {110, 0}) || ImGui::IsKeyPressed(GLFW_KEY_ENTER) || ImGui::IsKeyPressed(GLFW_KEY_ESCAPE)) {
      error_text_.clear();
      ImGui::CloseCurrentPopup();
    }
    ImGui::EndPopup();
  }

  if (show_shortcuts_) {
    ImGui::SetNextWindowSize({520, 0}, ImGuiCond_Appearing);
    if (ImGui::Begin("Keyboard and Mouse", &show_shortcuts_, ImGuiWindowFlags_NoSavedSettings)) {
      static constexpr const char* kRows[][2] = {
          {"Tab / right-click", "add a node or library asset (type to search)"},
          {"drag pin to pin", "connect (incompatible pins dim)"},
          {"drag from a connected input", "move or detach its link"},
          {"click / Shift-click / drag on empty", "select / toggle / box select"},
          {"drag a node", "move the selection"},
          {"Delete / X", "delete"},
          {"Ctrl+D, Ctrl+C, Ctrl+V", "duplicate, copy, paste (graph JSON)"},
          {"F / Home", "frame selected / all"},
          {"middle drag or Space+drag, wheel", "pan, zoom around the cursor"},
          {"double-click a node", "pin the preview to it (an instance: enter it)"},
          {"Ctrl+G / Ctrl+Shift+G", "group the selection into a subgraph / ungroup"},
          {"Tab on an instance / Shift+Tab", "enter the subgraph / leave it (or click a breadcrumb)"},
          {"Ctrl+Z / Ctrl+Shift+Z", "undo / redo"},
          {"Ctrl+S, Ctrl+Shift+S, Ctrl+O, Ctrl+N", "save, save as, open, new"},
          {"Ctrl+B", "build (resolution: Build > Resolution)"},
          {"3D: left / right drag, wheel, F", "orbit / pan, zoom, frame"},
      };
      if (ImGui::BeginTable("##keys", 2, ImGuiTableFlags_RowBg)) {
        for (const auto& row : kRows) {
          ImGui::TableNextRow();
          ImGui::TableSetColumnIndex(0);
          ImGui::TextUnformatted(row[0]);
          ImGui::TableSetColumnIndex(1);
          ImGui::TextDisabled("%s", row[1]);
        }
        ImGui::EndTable();
      }
    }
    ImGui::End();
  }
  if (show_node_libraries_) draw_node_libraries_window();
  if (show_about_) {
    if (ImGui::Begin("About Orogen", &show_about_,
                     ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoSavedSettings)) {
      ImGui::Text("Orogen %s", OROGEN_VERSION);
      ImGui::TextDisabled("A node-graph procedural terrain compositor.");
      ImGui::Text("%zu node types registered.", NodeRegistry::instance().all().size());
      ImGui::TextDisabled("Dear ImGui %s, OpenGL %s", ImGui::GetVersion(),
                          reinterpret_cast<const char*>(glGetString(GL_VERSION)));
    }
    ImGui::End();
  }
}

// The loaded node libraries with their types, the ones that failed and why, and the preferences' list: a
// library added here loads at once and at every start; one removed stays loaded until the editor restarts.
void App::draw_node_libraries_window() {
  ImGui::SetNextWindowSize({620, 360}, ImGuiCond_FirstUseEver);
  if (ImGui::Begin("Node Libraries", &show_node_libraries_, ImGuiWindowFlags_NoSavedSettings)) {
    const auto loaded = loaded_node_libraries();
    if (loaded.empty()) ImGui::TextDisabled("No node library is loaded.");
    for (const auto& lib : loaded) {
      ImGui::Text("%s", lib.name.c_str());
      ImGui::SameLine();
      ImGui::TextDisabled("%s", lib.path.string().c_str());
      std::string types;
      for (const auto& t : lib.types) types += (types.empty() ? "" : ", ") + t;
      ImGui::TextWrapped("  %s", types.c_str());
    }
    for (const auto& e : node_library_errors_) ImGui::TextColored({1.0f, 0.45f, 0.4f, 1.0f}, "%s", e.c_str());
    ImGui::Separator();
    ImGui::TextUnformatted("Loaded at every start (besides OROGEN_PLUGIN_PATH):");
    std::filesystem::path remove;
    for (const auto& f : node_libraries_.files()) {
      ImGui::PushID(f.string().c_str());
      if (ImGui::SmallButton("Remove")) remove = f;
      ImGui::PopID();
      ImGui::SameLine();
      ImGui::TextUnformatted(f.string().c_str());
    }
    if (!remove.empty()) node_libraries_.remove(remove);
    ImGui::SetNextItemWidth(-80);
    const bool enter = ImGui::InputText("##library", &node_library_entry_, ImGuiInputTextFlags_EnterReturnsTrue);
    ImGui::SameLine();
    if ((ImGui::Button("Add") || enter) && !node_library_entry_.empty()) {
      try {
        load_node_library(node_library_entry_);
        node_libraries_.add(node_library_entry_);
        node_library_entry_.clear();
      } catch (const std::exception& e) {
        node_library_errors_.push_back(e.what());
      }
    }
  }
  ImGui::End();
}

void App::set_document(std::unique_ptr<Document> document) {
  // The old document's unsaved work is gone by the user's choice; so is its recovery file.
  recovery_.discard();
  autosaver_.reset();
  document_ = std::move(document);
  navigator_->set_root(*document_);
  canvas_->set_document(*document_);
  canvas_view_->document_changed();
  pinned_.clear();
  drape_node_.clear();
  shown_port_.clear();
  requested_revision_ = ~std::uint64_t(0);
  thumbnails_revision_ = 0;
  frame_canvas_ = true;
  build_choice_.clear();  // another file: its own resolution
}

void App::open_file(const std::filesystem::path& path) {
  try {
    set_document(std::make_unique<Document>(Document::open(path, canvas_->thumbnails())));
    recent_.add(path);
  } catch (const std::exception& e) {
    show_error(e.what());
    recent_.remove(path);
  }
}

bool App::save() {
  if (!document_->has_path()) return false;
  try {
    document_->save();
    recent_.add(document_->path());
    recovery_.discard();
    return true;
  } catch (const std::exception& e) {
    show_error(std::string("Saving failed, nothing was overwritten:\n") + e.what());
    return false;
  }
}

void App::save_as(const std::filesystem::path& path) {
  try {
    document_->save_as(path);
    recent_.add(path);
    recovery_.discard();
  } catch (const std::exception& e) {
    show_error(std::string("Saving failed, nothing was overwritten:\n") + e.what());
  }
}

void App::guard_unsaved(std::function<void()> action) {
  if (!document_->dirty()) {
    action();
    return;
  }
  pending_action_ = std::move(action);
  prompt_unsaved_ = true;
}

void App::request_quit() {
  guard_unsaved([this] { quit_ = true; });
}

std::vector<std::filesystem::path> App::examples() const {
  std::vector<std::filesystem::path> dirs;
  if (!options_.examples_dir.empty()) dirs.push_back(options_.examples_dir);
  dirs.push_back("graphs");
  dirs.push_back(std::filesystem::path(OROGEN_SOURCE_DIR) / "graphs");
  std::vector<std::filesystem::path> out;
  for (const auto& d : dirs) {
    std::error_code ec;
    if (!std::filesystem::is_directory(d, ec)) continue;
    for (const auto& e : std::filesystem::directory_iterator(d, ec))
      if (e.path().extension() == ".json") out.push_back(std::filesystem::absolute(e.path(), ec));
    if (!out.empty()) break;
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::string App::preview_node() const {
  const Graph& g = doc().graph();
  auto viewable = [&](const std::string& id) -> std::string {
    const Node* n = g.find(id);
    if (!n) return {};
    if (!n->type->outputs.empty() || is_scene_writer(*n)) return id;  // a scene writer shows its scene
    // A writer shows what it writes.
    for (const auto& in : n->type->inputs)
      if (auto it = n->inputs.find(in.name); it != n->inputs.end()) return it->second.node;
    return {};
  };
  if (!pinned_.empty())
    if (auto id = viewable(pinned_); !id.empty()) return id;
  if (!selection_.active().empty())
    if (auto id = viewable(selection_.active()); !id.empty()) return id;
  // Nothing chosen: the heightfield or scene the graph writes (what a build produces), else the last
  // heightfield of the flow, else the last node with outputs.
  std::vector<std::string> order;
  try {
    order = g.topological_order();
  } catch (const std::exception&) {
    return {};
  }
  auto first_output_is_field = [&](const std::string& id) {
    const Node* n = g.find(id);
    return n && !n->type->outputs.empty() && n->type->outputs.front().type == PortType::Heightfield;
  };
  for (auto it = order.rbegin(); it != order.rend(); ++it)
    if (const Node* n = g.find(*it); n && n->type->writes_files)
      if (auto id = viewable(*it); first_output_is_field(id) || (id == *it && is_scene_writer(*n))) return id;
  for (auto it = order.rbegin(); it != order.rend(); ++it)
    if (first_output_is_field(*it)) return *it;
  for (auto it = order.rbegin(); it != order.rend(); ++it)
    if (auto id = viewable(*it); !id.empty()) return id;
  return {};
}

std::vector<std::string> App::preview_request(const std::string& node) const {
  std::vector<std::string> nodes;
  const Node* n = doc().graph().find(node);
  if (!n) return nodes;
  if (const auto scene = scene_sources(doc().graph(), node)) {
    // A writer itself is not evaluated (it would write files): the nodes feeding it are. A node making a
    // scene (Instance) is evaluated with the ground under it.
    nodes = scene->nodes();
    if (show_3d_ && !drape_node_.empty() && doc().graph().find(drape_node_) &&
        std::find(nodes.begin(), nodes.end(), drape_node_) == nodes.end())
      nodes.push_back(drape_node_);
    return nodes;
  }
  nodes.push_back(node);
  const int port = std::clamp(shown_port_.count(node) ? shown_port_.at(node) : 0, 0,
                              std::max(0, static_cast<int>(n->type->outputs.size()) - 1));
  const bool field =
      n->type->outputs.empty() || n->type->outputs[static_cast<std::size_t>(port)].type == PortType::Heightfield;
  // Water depth is shown on the terrain it lies in.
  const bool water = field && !n->type->outputs.empty() &&
                     output_kind(node, n->type->outputs[static_cast<std::size_t>(port)].name) == OutputKind::WaterDepth;
  if (!field || water) {
    // Points, curves, maps and meshes are drawn over the heightfield they came from; images are draped
    // over it in 3D.
    for (const auto& in : n->type->inputs)
      if (in.type == PortType::Heightfield)
        if (auto it = n->inputs.find(in.name); it != n->inputs.end()) {
          nodes.push_back(it->second.node);
          break;
        }
  }
  if (show_3d_ && !drape_node_.empty() && doc().graph().find(drape_node_) && drape_node_ != node)
    nodes.push_back(drape_node_);
  return nodes;
}

void App::update_preview() {
  // Thumbnails follow the content once the preview is done (they never delay it).
  if (canvas_->thumbnails() && !evaluation_.preview_busy() && !pending_request_ &&
      thumbnails_revision_ != preview_revision() + 1) {
    evaluation_.request_thumbnails(preview_graph(), preview_revision(), &doc().graph());
    thumbnails_revision_ = preview_revision() + 1;  // + 1: 0 means none requested
  }
  const std::string node = preview_node();
  const auto nodes = preview_request(node);
  const bool changed = preview_revision() != requested_revision_ || nodes != requested_nodes_ ||
                       evaluation_.preview_resolution() != requested_resolution_;
  pending_request_ = changed && !nodes.empty();
  if (!pending_request_) return;
  // While a run is busy, superseding it at most every few frames lets drags show intermediate results.
  const auto now = std::chrono::steady_clock::now();
  if (evaluation_.preview_busy() && now - last_request_ < kRequestThrottle) return;
  evaluation_.request_preview(preview_graph(), nodes, preview_revision());
  requested_revision_ = preview_revision();
  requested_nodes_ = nodes;
  requested_resolution_ = evaluation_.preview_resolution();
  last_request_ = now;
  pending_request_ = false;
}

// The first image output of the chosen drape node in the preview result, if any.
ImagePtr App::drape_image(const PreviewResult& result) const {
  if (drape_node_.empty()) return nullptr;
  if (auto it = result.outputs.find(drape_node_); it != result.outputs.end())
    for (const auto& v : it->second)
      if (auto* im = std::get_if<ImagePtr>(&v)) return *im;
  return nullptr;
}

PreviewContent App::preview_content(const std::string& node) const {
  PreviewContent c;
  c.node = node;
  const Node* n = node.empty() ? nullptr : doc().graph().find(node);
  if (n)
    if (const auto sources = scene_sources(doc().graph(), node)) return scene_content(node, *sources);
  if (!n || n->type->outputs.empty()) return c;
  const int port =
      std::clamp(shown_port_.count(node) ? shown_port_.at(node) : 0, 0, static_cast<int>(n->type->outputs.size()) - 1);
  c.port = n->type->outputs[static_cast<std::size_t>(port)].name;
  if (n->type->outputs[static_cast<std::size_t>(port)].type == PortType::Heightfield)
    c.kind = output_kind(node, c.port);
  const auto result = evaluation_.preview();
  c.stale = evaluation_.preview_busy() || pending_request_;
  if (!result) return c;
  c.serial = result->serial;
  if (auto it = result->outputs.find(node);
      it != result->outputs.end() && static_cast<std::size_t>(port) < it->second.size())
    c.value = it->second[static_cast<std::size_t>(port)];
  if (auto it = result->reports.find(node); it != result->reports.end() && (it->second.status == NodeStatus::Failed ||
                                                                            it->second.status == NodeStatus::Skipped))
    c.error = it->second.status == NodeStatus::Failed
                  ? node + " failed: " + it->second.message
                  : node + " is not evaluated: upstream node '" + it->second.message + "' failed";
  if (!result->error.empty()) c.error = result->error;
  const auto nodes = preview_request(node);
  if (nodes.size() > 1 && nodes[1] != drape_node_)
    if (auto it = result->outputs.find(nodes[1]); it != result->outputs.end())
      for (const auto& v : it->second)
        if (auto* h = std::get_if<HeightfieldPtr>(&v)) {
          c.backdrop = *h;
          c.backdrop_node = nodes[1];
          break;
        }
  if (auto* image = std::get_if<ImagePtr>(&c.value); image && *image && drape_node_.empty()) c.drape = *image;
  if (ImagePtr drape = drape_image(*result)) c.drape = drape;
  return c;
}

PreviewContent App::scene_content(const std::string& node, const SceneSources& sources) const {
  PreviewContent c;
  c.node = node;
  c.port = sources.writer ? "in" : sources.scene.port;  // what is shown: the scene's instances
  const auto result = evaluation_.preview();
  c.stale = evaluation_.preview_busy() || pending_request_;
  if (sources.scene.node.empty()) {
    c.error = node + ": connect the scene to write (input in, from Instance)";
    return c;
  }
  if (!result) return c;
  c.serial = result->serial;
  // The first source that failed explains the missing scene.
  for (const std::string& id : sources.nodes())
    if (auto it = result->reports.find(id); it != result->reports.end() && (it->second.status == NodeStatus::Failed ||
                                                                            it->second.status == NodeStatus::Skipped)) {
      c.error = it->second.status == NodeStatus::Failed
                    ? id + " failed: " + it->second.message
                    : id + " is not evaluated: upstream node '" + it->second.message + "' failed";
      break;
    }
  if (!result->error.empty()) c.error = result->error;
  ScenePreview scene = assemble_scene(doc().graph(), sources, result->outputs);
  if (scene.points) c.value = scene.points;
  if (scene.ground) {
    c.backdrop = scene.ground;
    c.backdrop_node = sources.ground.node;
  }
  if (ImagePtr drape = drape_image(*result)) c.drape = drape;
  if (scene.scene) c.scene = std::move(scene);
  return c;
}

glm::ivec2 App::build_samples() const {
  const auto& domain = doc().graph().domain;
  if (!build_choice_.empty())
    for (const auto& c : build_resolutions(domain))
      if (c.name == build_choice_) return c.samples;
  return domain.resolution;
}

void App::start_build() {
  if (evaluation_.build_status().running) return;
  OutputPolicy policy;
  policy.output_dir = output_dir_;
  evaluation_.start_build(graph_at_resolution(document_->graph(), build_samples()), policy);
}

void App::level_changed() {
  // Another level's nodes: nothing of the preview state of the last one applies.
  shown_level_ = &doc();
  // Inside an instance, its nodes are previewed in the root graph, fed by the instance's inputs.
  evaluation_.set_context(navigator_->inside() ? navigator_->instance_path() + "/" : std::string());
  canvas_view_->document_changed();
  pinned_.clear();
  shown_port_.clear();
  if (!doc().graph().find(drape_node_)) drape_node_.clear();
  requested_revision_ = ~std::uint64_t(0);
  thumbnails_revision_ = 0;
}

void App::draw_breadcrumbs() {
  if (!navigator_->inside()) return;
  // Where the canvas is: the graph file, then each instance entered; a click goes back to that level.
  const auto crumbs = navigator_->breadcrumbs();
  ImGui::SetCursorPos({10, 8});
  ImGui::PushStyleColor(ImGuiCol_Button, ImVec4(0.16f, 0.18f, 0.21f, 0.92f));
  for (std::size_t k = 0; k < crumbs.size(); ++k) {
    if (k > 0) {
      ImGui::SameLine(0, 6);
      ImGui::TextUnformatted(">");
      ImGui::SameLine(0, 6);
    }
    ImGui::PushID(static_cast<int>(k));
    const bool here = k + 1 == crumbs.size();
    if (here) ImGui::PushStyleColor(ImGuiCol_Button, ImVec4(0.24f, 0.36f, 0.52f, 0.95f));
    if (ImGui::Button(crumbs[k].c_str()) && !here) canvas_->leave_subgraph_to(k);
    if (here) ImGui::PopStyleColor();
    if (ImGui::IsItemHovered())
      ImGui::SetTooltip(here ? "Editing this asset: changes are saved to %s and every instance follows"
                             : "Back to this level (Shift+Tab leaves one level)",
                        navigator_->levels().back().file.string().c_str());
    ImGui::PopID();
  }
  ImGui::PopStyleColor();
}

OutputKind App::output_kind(const std::string& node, const std::string& port) const {
  if (!navigator_->inside()) return resolve_output_kind(doc().graph(), node, port);
  // Inner inputs fed by the interface are unconnected in the asset: follow them in the expanded root.
  if (kind_graph_revision_ != preview_revision()) {
    kind_graph_revision_ = preview_revision();
    kind_graph_.reset();
    try {
      kind_graph_ = expand_subgraphs(document_->graph()).graph;
    } catch (const std::exception&) {
      // An invalid root: the asset's own links are all there is to go by.
    }
  }
  const std::string id = navigator_->instance_path() + "/" + node;
  if (!kind_graph_ || !kind_graph_->find(id)) return resolve_output_kind(doc().graph(), node, port);
  return resolve_output_kind(*kind_graph_, id, port);
}

}  // namespace orogen::editor
