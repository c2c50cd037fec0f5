#include "editor/ui/file_dialog.h"

#include <algorithm>
#include <cctype>
#include <cstdint>

#include <imgui.h>
#include <imgui_stdlib.h>

namespace orogen::editor {

namespace {
std::string lower(std::string s) {
  for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}
}  // namespace

void FileDialog::show(Mode mode, std::string title, const std::filesystem::path& start,
                      std::vector<std::string> extensions) {
  mode_ = mode;
  title_ = std::move(title);
  extensions_ = std::move(extensions);
  std::error_code ec;
  std::filesystem::path p = start.empty() ? std::filesystem::current_path(ec) : std::filesystem::absolute(start, ec);
  if (std::filesystem::is_directory(p, ec)) {
    dir_ = p;
    name_.clear();
  } else {
    dir_ = p.parent_path();
    name_ = p.filename().string();
  }
  dir_text_ = dir_.string();
  error_.clear();
  pending_open_ = true;
  list_directory();
}

bool FileDialog::matches(const std::filesystem::path& p) const {
  if (extensions_.empty()) return true;
  const auto ext = lower(p.extension().string());
  return std::find(extensions_.begin(), extensions_.end(), ext) != extensions_.end();
}

void FileDialog::list_directory() {
  dirs_.clear();
  files_.clear();
  std::error_code ec;
  for (const auto& e :
       std::filesystem::directory_iterator(dir_, std::filesystem::directory_options::skip_permission_denied, ec)) {
    const auto name = e.path().filename().string();
    if (name.empty() || name[0] == '.') continue;
    std::error_code ec2;
    if (e.is_directory(ec2))
      dirs_.push_back(e.path());
    else if (matches(e.path()))
      files_.push_back(e.path());
  }
  if (ec) error_ = "cannot list " + dir_.string() + ": " + ec.message();
  std::sort(dirs_.begin(), dirs_.end());
  std::sort(files_.begin(), files_.end());
}

std::optional<std::filesystem::path> FileDialog::draw() {
  // The id stays the same whatever the title, and differs between dialog instances.
  const std::string popup = title_ + "###file-dialog-" + std::to_string(reinterpret_cast<std::uintptr_t>(this));
  if (pending_open_) {
    ImGui::OpenPopup(popup.c_str());
    pending_open_ = false;
    visible_ = true;
  }
  if (!visible_) return std::nullopt;
  std::optional<std::filesystem::path> chosen;
  ImGui::SetNextWindowSize({640, 460}, ImGuiCond_Appearing);
  if (!ImGui::BeginPopupModal(popup.c_str(), nullptr)) {
    visible_ = false;
    return std::nullopt;
  }
  ImGui::SetNextItemWidth(-70);
  if (ImGui::InputText("##dir", &dir_text_, ImGuiInputTextFlags_EnterReturnsTrue)) {
    std::error_code ec;
    if (std::filesystem::is_directory(dir_text_, ec)) {
      dir_ = std::filesystem::absolute(dir_text_, ec);
      list_directory();
    } else {
      error_ = "not a folder: " + dir_text_;
    }
  }
  ImGui::SameLine();
  if (ImGui::Button("Up", {-1, 0}) && dir_.has_parent_path()) {
    dir_ = dir_.parent_path();
    dir_text_ = dir_.string();
    list_directory();
  }

  const float footer = ImGui::GetFrameHeightWithSpacing() * 2 + 8;
  ImGui::BeginChild("##list", {0, -footer}, true);
  std::optional<std::filesystem::path> enter;
  for (const auto& d : dirs_) {
    std::string label = d.filename().string();
    label += "/";
    if (ImGui::Selectable(label.c_str(), false, ImGuiSelectableFlags_AllowDoubleClick) &&
        ImGui::IsMouseDoubleClicked(0))
      enter = d;
  }
  for (const auto& f : files_) {
    const auto name = f.filename().string();
    if (ImGui::Selectable(name.c_str(), name == name_, ImGuiSelectableFlags_AllowDoubleClick)) {
      name_ = name;
      if (ImGui::IsMouseDoubleClicked(0)) chosen = f;
    }
  }
  if (dirs_.empty() && files_.empty()) ImGui::TextDisabled("(empty)");
  ImGui::EndChild();
  if (enter) {
    dir_ = *enter;
    dir_text_ = dir_.string();
    list_directory();
  }

  ImGui::SetNextItemWidth(-200);
  const bool typed_enter =
      ImGui::InputTextWithHint("##name", "file name", &name_, ImGuiInputTextFlags_EnterReturnsTrue);
  ImGui::SameLine();
  const bool ok = ImGui::Button(mode_ == Mode::Open ? "Open" : "Save", {90, 0});
  ImGui::SameLine();
  const bool cancel = ImGui::Button("Cancel", {-1, 0}) || ImGui::IsKeyPressed(ImGui::GetKeyIndex(ImGuiKey_Escape));
  if ((ok || typed_enter) && !name_.empty()) {
    std::filesystem::path p = std::filesystem::path(name_).is_absolute() ? std::filesystem::path(name_) : dir_ / name_;
    if (mode_ == Mode::Save && !extensions_.empty() && !matches(p)) p += extensions_.front();
    std::error_code ec;
    if (mode_ == Mode::Open && !std::filesystem::is_regular_file(p, ec))
      error_ = "no such file: " + p.string();
    else
      chosen = p;
  }
  if (!error_.empty())
    ImGui::TextColored({1.0f, 0.4f, 0.35f, 1.0f}, "%s", error_.c_str());
  else if (mode_ == Mode::Save && !name_.empty() && std::filesystem::exists(dir_ / name_))
    ImGui::TextDisabled("%s exists and will be replaced", name_.c_str());
  if (chosen || cancel) {
    ImGui::CloseCurrentPopup();
    visible_ = false;
  }
  ImGui::EndPopup();
  return chosen;
}

}  // namespace orogen::editor
