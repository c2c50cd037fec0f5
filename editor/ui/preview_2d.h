#pragma once
// The 2D preview: heightfields through a colour map with hillshade, images, and points, curves and polygon
// maps drawn over their terrain; pan (drag) and zoom (wheel) in world units; the world position and value
// under the cursor.
#include <cstdint>
#include <optional>
#include <string>

#include <glm/vec2.hpp>

#include "editor/model/preview_image.h"
#include "editor/ui/gl_texture.h"
#include "editor/ui/preview_panel.h"

namespace orogen::editor {

class Preview2D {
 public:
  void draw(const PreviewContent& content);
  // Choices at start (command line): the image channel shown, by name, once an image with it is shown; the
  // colour map by name ("" leaves either automatic).
  void set_start(const std::string& channel, const std::string& color_map);

 private:
  void upload(const PreviewContent& content);
  // The image channel chosen for display as a field, or null (composite, or the value is not an image).
  HeightfieldPtr chosen_channel(const PreviewContent& content);
  void fit(const Domain& domain, glm::dvec2 size);

  HeightfieldStyle style_for_content(const PreviewContent& content) const;

  HeightfieldStyle style_;        // the style drawn
  int map_choice_ = 0;            // 0: from the output's kind, else 1 + ColorMap
  int channel_choice_ = 0;        // images: 0 shows the colour composite, k > 0 channel k - 1 as a field
  HeightfieldPtr channel_field_;  // that channel
  ImagePtr channel_source_;       // the image and channel it was taken from
  int channel_source_index_ = -1;
  std::string start_channel_;             // set_start: applied when an image with this channel is shown
  std::optional<bool> hillshade_choice_;  // unset: from the output's kind
  GlTexture texture_;
  std::string texture_key_;     // what the texture holds
  HeightfieldPtr shown_field_;  // held so their addresses in the key stay theirs
  ImagePtr shown_image_;
  HeightfieldPtr shown_under_;  // the terrain under water depth
  Domain texture_domain_;
  ValueRange shown_range_;
  bool has_range_ = false;
  // View: world point at the panel centre and pixels per metre; refitted when the domain changes.
  glm::dvec2 center_{0.0};
  double scale_ = 1.0;
  Domain fitted_domain_;
  bool fitted_ = false;
  glm::dvec2 panel_size_{0.0};
  std::string polygon_attribute_;  // cell attribute colouring a polygon map ("" = biome if present)
  Domain polygon_domain_;          // a polygon map's rectangle, when it is what is shown
};

}  // namespace orogen::editor
