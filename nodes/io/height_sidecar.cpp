#include "nodes/io/height_sidecar.h"

#include <nlohmann/json.hpp>

namespace orogen {

std::string height_sidecar_json(const Domain& d, HeightFormat format, const HeightRange& range,
                                const std::string& image_file_name) {
  nlohmann::ordered_json j;
  j["image"] = image_file_name;
  j["format"] = to_string(format);
  j["samples"] = {d.width(), d.height()};
  j["rows"] = "north first";
  j["height_at_0"] = range.min;  // metres stored as 0
  j["height_at_65535"] = range.max;
  j["cell_size"] = {d.spacing.x, d.spacing.y};  // metres between samples
  j["south_west_sample"] = {d.x(0), d.y(0)};
  // Unreal: X/Y scale is centimetres per sample; a Z scale of 100 maps 0..65535 onto 512 m (-256..+256 m
  // around the actor's Z), so the range needs (max - min) / 512 m * 100, and the actor sits at the middle.
  j["unreal"] = {{"scale_x", d.spacing.x * 100.0},
                 {"scale_y", d.spacing.y * 100.0},
                 {"scale_z", (range.max - range.min) / 512.0 * 100.0},
                 {"location_z_cm", (range.max + range.min) / 2.0 * 100.0}};
  return j.dump(2) + "\n";
}

}  // namespace orogen
