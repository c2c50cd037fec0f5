#include "editor/ui/preview_2d.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <imgui.h>

#include "editor/ui/theme.h"
#include "graph/curves.h"
#include "graph/mesh.h"
#include "graph/points.h"
#include "graph/polygon_map.h"

namespace orogen::editor {

namespace {

const Domain* domain_of(const PreviewContent& c, Domain& polygon_domain) {
  if (auto* h = std::get_if<HeightfieldPtr>(&c.value); h && *h) return &(*h)->domain;
  if (auto* i = std::get_if<ImagePtr>(&c.value); i && *i) return &(*i)->domain;
  if (c.backdrop) return &c.backdrop->domain;
  if (auto* m = std::get_if<PolygonMapPtr>(&c.value); m && *m) {
    // A polygon map without a terrain under it is framed by its own rectangle.
    const glm::dvec2 size = glm::max((*m)->max_corner - (*m)->min_corner, glm::dvec2(1e-6));
    polygon_domain = Domain::from_extent((*m)->min_corner, size, {2, 2});
    return &polygon_domain;
  }
  if (auto* cv = std::get_if<CurvesPtr>(&c.value); cv && *cv && (*cv)->vertex_count() > 0) {
    // Curves without a terrain under them are framed by their bounding box.
    glm::dvec2 lo(1e300), hi(-1e300);
    for (const auto& curve : (*cv)->curves)
      for (const auto& p : curve.points)
        if (std::isfinite(p.x) && std::isfinite(p.y)) {
          lo = glm::min(lo, glm::dvec2(p.x, p.y));
          hi = glm::max(hi, glm::dvec2(p.x, p.y));
        }
    if (!(lo.x <= hi.x)) return nullptr;
    polygon_domain = Domain::from_extent(lo, glm::max(hi - lo, glm::dvec2(1e-6)), {2, 2});
    return &polygon_domain;
  }
  return nullptr;
}

// Biome colours of the island family (A. Patel's palette, in the order of nodes/island/island.h's Biome:
// snow ... ocean), sRGB.
constexpr ImU32 kBiomeColors[16] = {
    IM_COL32(0xff, 0xff, 0xff, 255), IM_COL32(0xbb, 0xbb, 0xaa, 255), IM_COL32(0x88, 0x88, 0x88, 255),
    IM_COL32(0x55, 0x55, 0x55, 255), IM_COL32(0x99, 0xaa, 0x77, 255), IM_COL32(0x88, 0x99, 0x77, 255),
    IM_COL32(0xc9, 0xd2, 0x9b, 255), IM_COL32(0x44, 0x88, 0x55, 255), IM_COL32(0x67, 0x94, 0x59, 255),
    IM_COL32(0x88, 0xaa, 0x55, 255), IM_COL32(0x33, 0x77, 0x55, 255), IM_COL32(0x55, 0x99, 0x44, 255),
    IM_COL32(0xd2, 0xb9, 0x8b, 255), IM_COL32(0xa0, 0x90, 0x77, 255), IM_COL32(0x33, 0x66, 0x99, 255),
    IM_COL32(0x44, 0x44, 0x7a, 255)};

// A perceptual ramp (dark blue - teal - yellow) for any other attribute over its range.
ImU32 ramp_color(float t) {
  t = std::clamp(t, 0.0f, 1.0f);
  const float r = 0.27f + t * (0.99f - 0.27f) * t, g = 0.00f + 0.9f * t,
              b = 0.33f + 0.25f * std::sin(3.14159f * t) - 0.2f * t;
  return ImColor(r, g, std::clamp(b, 0.0f, 1.0f), 1.0f);
}

ImU32 marker_color_u32(int cls) {
  const glm::vec4 c = marker_color(cls);
  return ImColor(c.r, c.g, c.b, c.a);
}

}  // namespace

void Preview2D::fit(const Domain& domain, glm::dvec2 size) {
  const glm::dvec2 extent = glm::max(domain.size() + domain.spacing, glm::dvec2(1e-9));
  center_ = (domain.min_corner() + domain.max_corner()) * 0.5;
  scale_ = std::min(size.x / extent.x, size.y / extent.y) * 0.96;
  fitted_domain_ = domain;
  fitted_ = true;
}

void Preview2D::set_start(const std::string& channel, const std::string& color_map) {
  start_channel_ = channel;
  for (int k = 0; k < kColorMapCount; ++k)
    if (color_map == kColorMapNames[k]) map_choice_ = k + 1;
}

HeightfieldPtr Preview2D::chosen_channel(const PreviewContent& content) {
  const auto* i = std::get_if<ImagePtr>(&content.value);
  if (!i || !*i || channel_choice_ <= 0) return nullptr;
  if (channel_choice_ > (*i)->channels) {
    channel_choice_ = 0;
    return nullptr;
  }
  if (channel_source_ != *i || channel_source_index_ != channel_choice_ - 1) {
    channel_field_ = std::make_shared<Heightfield>(image_channel(**i, channel_choice_ - 1));
    channel_source_ = *i;
    channel_source_index_ = channel_choice_ - 1;
  }
  return channel_field_;
}

HeightfieldStyle Preview2D::style_for_content(const PreviewContent& content) const {
  // The backdrop under points and curves, and a value without a kind, are terrain; an image channel is a
  // scalar.
  const bool value_field = std::holds_alternative<HeightfieldPtr>(content.value);
  const bool image_channel = std::holds_alternative<ImagePtr>(content.value) && channel_choice_ > 0;
  HeightfieldStyle s = style_for(image_channel ? OutputKind::Scalar : value_field ? content.kind : OutputKind::Height);
  if (map_choice_ > 0) s.map = static_cast<ColorMap>(map_choice_ - 1);
  if (hillshade_choice_) s.hillshade = *hillshade_choice_;
  return s;
}

void Preview2D::upload(const PreviewContent& content) {
  // The texture shows the value itself (heightfield or image) or the backdrop heightfield.
  HeightfieldPtr field;
  ImagePtr image;
  if (auto* h = std::get_if<HeightfieldPtr>(&content.value))
    field = *h;
  else if (auto* i = std::get_if<ImagePtr>(&content.value))
    image = *i;
  else
    field = content.backdrop;
  if (HeightfieldPtr channel = chosen_channel(content)) {
    field = channel;
    image = nullptr;
  }
  style_ = style_for_content(content);
  // Redrawn when the data or the style change: results are immutable and shared, so the same pointer means
  // the same data (a cached result after an edit elsewhere is not redrawn). The pointers are held, so they
  // cannot be reused for other data meanwhile.
  // Water depth lies on its terrain (unless another colour map is chosen).
  const HeightfieldPtr under =
      field && content.kind == OutputKind::WaterDepth && map_choice_ == 0 ? content.backdrop : nullptr;
  char key[256];
  std::snprintf(key, sizeof key, "%p|%p|%p|%d|%d|%d|%d", static_cast<const void*>(field.get()),
                static_cast<const void*>(image.get()), static_cast<const void*>(under.get()),
                static_cast<int>(style_.map), style_.hillshade ? 1 : 0, style_.range ? 1 : 0, style_.symmetric ? 1 : 0);
  if (texture_key_ == key) return;
  texture_key_ = key;
  shown_field_ = field;
  shown_image_ = image;
  has_range_ = false;
  shown_under_ = under;
  if (field) {
    const auto px = under ? render_water_over_terrain(*under, *field) : render_heightfield(*field, style_);
    texture_.upload(px.width, px.height, px.rgba.data());
    texture_domain_ = under ? under->domain : field->domain;
    shown_range_ = style_range(*field, style_);
    has_range_ = true;
  } else if (image) {
    const auto px = render_image(*image);
    texture_.upload(px.width, px.height, px.rgba.data());
    texture_domain_ = image->domain;
  } else {
    texture_ = GlTexture();
  }
}

void Preview2D::draw(const PreviewContent& content) {
  // The colour map applies when a heightfield is drawn: the value itself, or the backdrop of points,
  // curves and maps (an image is drawn as it is).
  const auto* shown_image = std::get_if<ImagePtr>(&content.value);
  if (!start_channel_.empty() && shown_image && *shown_image) {
    const auto& names = (*shown_image)->channel_names;
    if (const auto it = std::find(names.begin(), names.end(), start_channel_); it != names.end()) {
      channel_choice_ = static_cast<int>(it - names.begin()) + 1;
      start_channel_.clear();
    }
  }
  const bool is_field = std::holds_alternative<HeightfieldPtr>(content.value) || (content.backdrop && !shown_image) ||
                        (shown_image && *shown_image && channel_choice_ > 0);
  // Toolbar.
  if (shown_image && *shown_image && (*shown_image)->channels > 1) {
    // Multi-channel images (monthly climate, splat weights): the colour composite or one channel.
    const Image& img = **shown_image;
    if (channel_choice_ > img.channels) channel_choice_ = 0;
    std::vector<std::string> names{"color"};
    for (int c = 0; c < img.channels; ++c)
      names.push_back(static_cast<std::size_t>(c) < img.channel_names.size() &&
                              !img.channel_names[static_cast<std::size_t>(c)].empty()
                          ? img.channel_names[static_cast<std::size_t>(c)]
                          : "channel " + std::to_string(c));
    ImGui::SetNextItemWidth(150);
    if (ImGui::BeginCombo("##channel", names[static_cast<std::size_t>(channel_choice_)].c_str())) {
      for (int k = 0; k < static_cast<int>(names.size()); ++k)
        if (ImGui::Selectable(names[static_cast<std::size_t>(k)].c_str(), k == channel_choice_)) channel_choice_ = k;
      ImGui::EndCombo();
    }
    if (ImGui::IsItemHovered())
      ImGui::SetTooltip("Channel: the first channels as color, or one channel (a month, a layer) through a color map");
    ImGui::SameLine();
  }
  if (is_field) {
    const HeightfieldStyle current = style_for_content(content);
    const bool value_field = std::holds_alternative<HeightfieldPtr>(content.value);
    const OutputKind shown_kind = shown_image ? OutputKind::Scalar : value_field ? content.kind : OutputKind::Height;
    char automatic[48];
    std::snprintf(automatic, sizeof automatic, "auto: %s", kColorMapNames[static_cast<int>(style_for(shown_kind).map)]);
    const char* items[1 + kColorMapCount] = {automatic};
    for (int k = 0; k < kColorMapCount; ++k) items[k + 1] = kColorMapNames[k];
    ImGui::SetNextItemWidth(120);
    if (ImGui::Combo("##map", &map_choice_, items, 1 + kColorMapCount) && map_choice_ == 0) hillshade_choice_.reset();
    if (ImGui::IsItemHovered())
      ImGui::SetTooltip(
          "Color map. Auto follows what the output holds (%s): heights in terrain tints, masks in "
          "gray over 0..1, signed fields diverging around 0, water depth in blues.",
          std::string(to_string(shown_kind)).c_str());
    ImGui::SameLine();
    bool shade = current.hillshade;
    if (ImGui::Checkbox("hillshade", &shade)) hillshade_choice_ = shade;
    ImGui::SameLine();
  }
  if (ImGui::Button("Fit") && domain_of(content, polygon_domain_)) fitted_ = false;
  if (has_range_) {
    ImGui::SameLine();
    ImGui::TextDisabled("%.4g .. %.4g", shown_range_.lo, shown_range_.hi);
  }
  if (auto* m = std::get_if<PolygonMapPtr>(&content.value); m && *m && !(*m)->cell_attributes.empty()) {
    // Which cell attribute colours the cells.
    const auto& attrs = (*m)->cell_attributes;
    if (!attrs.count(polygon_attribute_)) polygon_attribute_ = attrs.count("biome") ? "biome" : attrs.begin()->first;
    ImGui::SameLine();
    ImGui::SetNextItemWidth(140);
    if (ImGui::BeginCombo("##cell_attribute", polygon_attribute_.c_str())) {
      for (const auto& [name, values] : attrs)
        if (ImGui::Selectable(name.c_str(), name == polygon_attribute_)) polygon_attribute_ = name;
      ImGui::EndCombo();
    }
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("Cell attribute coloring the cells (biome: the biome colors)");
  }
  if (content.stale) {
    ImGui::SameLine();
    ImGui::TextColored(ImColor(theme::status_color(NodeRunState::Phase::Computing)), "updating");
  }

  const ImVec2 origin = ImGui::GetCursorScreenPos();
  ImVec2 size = ImGui::GetContentRegionAvail();
  size.y -= ImGui::GetTextLineHeightWithSpacing();
  size.x = std::max(size.x, 32.0f);
  size.y = std::max(size.y, 32.0f);
  panel_size_ = {size.x, size.y};
  ImGui::InvisibleButton("##preview2d", size, ImGuiButtonFlags_MouseButtonLeft | ImGuiButtonFlags_MouseButtonMiddle);
  const bool hovered = ImGui::IsItemHovered();
  ImDrawList* dl = ImGui::GetWindowDrawList();
  const ImVec2 end{origin.x + size.x, origin.y + size.y};
  dl->PushClipRect(origin, end, true);
  dl->AddRectFilled(origin, end, IM_COL32(22, 23, 26, 255));

  const Domain* domain = domain_of(content, polygon_domain_);
  if (!domain && !content.error.empty()) {
    ImGui::SetCursorScreenPos({origin.x + 12, origin.y + 12});
    ImGui::PushTextWrapPos(origin.x + size.x - 12 - ImGui::GetWindowPos().x);
    ImGui::TextColored(ImColor(theme::kError), "%s", content.error.c_str());
    ImGui::PopTextWrapPos();
    dl->PopClipRect();
    return;
  }
  if (auto* w = std::get_if<ModuleStringPtr>(&content.value); !domain && w && *w) {
    // An L-system word: its size and its beginning as text.
    const ModuleString& word = **w;
    std::string text = word.text();
    constexpr std::size_t kShown = 4000;
    const bool cut = text.size() > kShown;
    if (cut) text.resize(kShown);
    ImGui::SetCursorScreenPos({origin.x + 12, origin.y + 12});
    ImGui::PushTextWrapPos(origin.x + size.x - 12 - ImGui::GetWindowPos().x);
    ImGui::TextDisabled("%zu modules%s", word.size(), cut ? " (beginning shown)" : "");
    ImGui::TextUnformatted(text.c_str(), text.c_str() + text.size());
    ImGui::PopTextWrapPos();
    dl->PopClipRect();
    return;
  }
  if (!domain) {
    const char* text = content.node.empty()       ? "Select a node to preview it"
                       : has_value(content.value) ? "Nothing to draw in 2D for this output"
                                                  : "Waiting for the evaluation...";
    if (has_value(content.value) && std::holds_alternative<MeshPtr>(content.value)) text = "A mesh: see the 3D view";
    if (content.scene) text = "A scene without a ground under it: see the 3D view";
    const ImVec2 ts = ImGui::CalcTextSize(text);
    dl->AddText({origin.x + (size.x - ts.x) * 0.5f, origin.y + (size.y - ts.y) * 0.5f}, theme::kTextDim, text);
    dl->PopClipRect();
    ImGui::TextDisabled(" ");
    return;
  }
  upload(content);
  if (!fitted_ ||
      !(fitted_domain_.min_corner() == domain->min_corner() && fitted_domain_.max_corner() == domain->max_corner()))
    fit(*domain, panel_size_);

  const glm::dvec2 pc{origin.x + size.x * 0.5, origin.y + size.y * 0.5};
  auto to_screen = [&](glm::dvec2 w) {
    const glm::dvec2 s = pc + glm::dvec2(w.x - center_.x, -(w.y - center_.y)) * scale_;
    return ImVec2{static_cast<float>(s.x), static_cast<float>(s.y)};
  };
  auto to_world = [&](ImVec2 s) {
    return glm::dvec2(center_.x + (s.x - pc.x) / scale_, center_.y - (s.y - pc.y) / scale_);
  };

  // Pan and zoom.
  ImGuiIO& io = ImGui::GetIO();
  if (hovered && io.MouseWheel != 0.0f) {
    const glm::dvec2 anchor = to_world(io.MousePos);
    scale_ = std::clamp(scale_ * std::pow(1.2, io.MouseWheel), 1e-6, 1e6);
    center_ = anchor - glm::dvec2(io.MousePos.x - pc.x, -(io.MousePos.y - pc.y)) / scale_;
  }
  if (ImGui::IsItemActive() && (ImGui::IsMouseDragging(0) || ImGui::IsMouseDragging(2)))
    center_ -= glm::dvec2(io.MouseDelta.x, -io.MouseDelta.y) / scale_;

  if (texture_.valid()) {
    // Texels are centred on samples: the texture covers half a spacing beyond the border samples.
    const glm::dvec2 half = texture_domain_.spacing * 0.5;
    const ImVec2 a = to_screen({texture_domain_.min_corner().x - half.x, texture_domain_.max_corner().y + half.y});
    const ImVec2 b = to_screen({texture_domain_.max_corner().x + half.x, texture_domain_.min_corner().y - half.y});
    dl->AddImage(texture_.imgui_id(), a, b);
  }

  // Overlays.
  if (auto* p = std::get_if<PointsPtr>(&content.value); p && *p) {
    const Points& pts = **p;
    const float r = std::clamp(static_cast<float>(scale_ * 2.0), 1.5f, 5.0f);
    const std::size_t step = std::max<std::size_t>(1, pts.size() / 50000);
    for (std::size_t k = 0; k < pts.size(); k += step)
      dl->AddCircleFilled(to_screen({pts.position[k].x, pts.position[k].y}), r,
                          marker_color_u32(k < pts.class_id.size() ? pts.class_id[k] : 0), 8);
  } else if (auto* c = std::get_if<CurvesPtr>(&content.value); c && *c) {
    // Width-aware: each segment as wide as the curve there (world metres), at least 1.5 pixels; wider is
    // deeper blue. Round joints where the stroke is thick enough to show gaps.
    float max_width = 0.0f;
    for (const auto& curve : (*c)->curves)
      for (float wv : curve.width) max_width = std::max(max_width, wv);
    auto color = [&](float wv) {
      const float t = max_width > 0.0f ? std::clamp(wv / max_width, 0.0f, 1.0f) : 0.0f;
      return ImColor(0.55f - 0.45f * t, 0.85f - 0.4f * t, 1.0f - 0.1f * t, 1.0f);
    };
    for (const auto& curve : (*c)->curves) {
      const std::size_t n = curve.points.size();
      auto width_at = [&](std::size_t k) { return k < curve.width.size() ? curve.width[k] : 0.0f; };
      for (std::size_t k = 0; k + 1 < n; ++k) {
        const float wv = 0.5f * (width_at(k) + width_at(k + 1));
        const float px = std::max(1.5f, static_cast<float>(wv * scale_));
        const ImVec2 a = to_screen({curve.points[k].x, curve.points[k].y});
        const ImVec2 b = to_screen({curve.points[k + 1].x, curve.points[k + 1].y});
        dl->AddLine(a, b, color(wv), px);
        if (px > 3.0f) dl->AddCircleFilled(b, px * 0.5f, color(wv), 12);
      }
      if (n == 1) dl->AddCircleFilled(to_screen({curve.points[0].x, curve.points[0].y}), 2.0f, color(width_at(0)));
    }
  } else if (auto* m = std::get_if<PolygonMapPtr>(&content.value); m && *m) {
    const PolygonMap& map = **m;
    const auto corner_at = [&](int q) { return to_screen(map.corners[static_cast<std::size_t>(q)].position); };
    // Cells filled by the chosen attribute (biome ids in the biome colors, anything else on a ramp).
    const auto attr = map.cell_attributes.find(polygon_attribute_);
    const std::vector<float>* values =
        attr != map.cell_attributes.end() && attr->second.size() == map.cells.size() ? &attr->second : nullptr;
    float lo = 0.0f, hi = 1.0f;
    if (values && !values->empty()) {
      lo = *std::min_element(values->begin(), values->end());
      hi = *std::max_element(values->begin(), values->end());
    }
    const bool biome = polygon_attribute_ == "biome";
    std::vector<ImVec2> poly;
    for (std::size_t c = 0; c < map.cells.size(); ++c) {
      const auto& cell = map.cells[c];
      if (cell.corners.size() < 3) continue;
      poly.clear();
      for (int q : cell.corners) poly.push_back(corner_at(q));
      ImU32 col = IM_COL32(120, 120, 130, 255);
      if (values) {
        const float v = (*values)[c];
        col = biome ? kBiomeColors[static_cast<unsigned>(std::clamp(static_cast<int>(v), 0, 15))]
                    : ramp_color(hi > lo ? (v - lo) / (hi - lo) : 0.5f);
      }
      dl->AddConvexPolyFilled(poly.data(), static_cast<int>(poly.size()), col);
    }
    // Cell outlines when the cells are large enough on screen.
    const double cell_px =
        scale_ *
        std::sqrt(std::max(1e-12, (map.max_corner.x - map.min_corner.x) * (map.max_corner.y - map.min_corner.y) /
                                      static_cast<double>(std::max<std::size_t>(1, map.cells.size()))));
    const auto* ocean = map.cell_attributes.count("ocean") ? &map.cell_attributes.at("ocean") : nullptr;
    const auto* river = map.edge_attributes.count("river") ? &map.edge_attributes.at("river") : nullptr;
    for (std::size_t k = 0; k < map.edges.size(); ++k) {
      const auto& e = map.edges[k];
      if (e.corners[0] < 0 || e.corners[1] < 0) continue;
      const ImVec2 a = corner_at(e.corners[0]), b = corner_at(e.corners[1]);
      const bool coast = ocean && ocean->size() == map.cells.size() && e.cells[0] >= 0 && e.cells[1] >= 0 &&
                         ((*ocean)[static_cast<std::size_t>(e.cells[0])] > 0.5f) !=
                             ((*ocean)[static_cast<std::size_t>(e.cells[1])] > 0.5f);
      if (river && river->size() == map.edges.size() && (*river)[k] > 0.0f)
        dl->AddLine(a, b, IM_COL32(0x22, 0x55, 0x88, 255), std::clamp(1.0f + std::sqrt((*river)[k]), 1.0f, 6.0f));
      else if (coast)
        dl->AddLine(a, b, IM_COL32(40, 30, 20, 255), 2.0f);
      else if (cell_px > 8.0)
        dl->AddLine(a, b, IM_COL32(20, 20, 24, 70), 1.0f);
    }
  }
  // Outline of the domain.
  dl->AddRect(to_screen({domain->min_corner().x, domain->max_corner().y}),
              to_screen({domain->max_corner().x, domain->min_corner().y}), IM_COL32(255, 255, 255, 40));
  dl->PopClipRect();

  // Readout under the cursor.
  if (hovered) {
    const glm::dvec2 w = to_world(io.MousePos);
    char value[160] = "";
    HeightfieldPtr field = content.backdrop;
    if (auto* h = std::get_if<HeightfieldPtr>(&content.value)) field = *h;
    if (auto* im = std::get_if<ImagePtr>(&content.value); im && *im) {
      const Image& img = **im;
      const glm::dvec2 s = img.domain.to_sample(w);
      const int i = static_cast<int>(std::lround(s.x)), j = static_cast<int>(std::lround(s.y));
      if (i >= 0 && j >= 0 && i < img.width() && j < img.height()) {
        const float* px = img.pixel(i, j);
        int n = std::snprintf(value, sizeof value, "  value");
        for (int k = 0; k < std::min(img.channels, 4) && n < 150; ++k)
          n += std::snprintf(value + n, sizeof value - n, " %.3g", px[k]);
      }
    } else if (field) {
      const glm::dvec2 s = field->domain.to_sample(w);
      if (s.x >= -0.5 && s.y >= -0.5 && s.x <= field->width() - 0.5 && s.y <= field->height() - 0.5)
        std::snprintf(value, sizeof value, "  value %.5g", field->sample_world(w.x, w.y));
    }
    ImGui::Text("x %.1f m  y %.1f m%s", w.x, w.y, value);
  } else {
    // What the value is (a polygon map's frame is not a raster: its cells and extent are said).
    const std::string what = describe_preview_value(content.value, content.backdrop.get());
    ImGui::TextDisabled("%s.%s   %s", content.node.c_str(), content.port.c_str(), what.c_str());
  }
}

}  // namespace orogen::editor
