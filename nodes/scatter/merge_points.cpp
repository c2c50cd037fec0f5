#include "nodes/scatter/merge_points.h"

namespace orogen {

Points merge_points(const std::vector<const Points*>& sets) {
  Points out;
  for (const Points* in : sets) {
    if (!in) continue;
    const std::size_t base = out.size();
    out.position.insert(out.position.end(), in->position.begin(), in->position.end());
    out.rotation.insert(out.rotation.end(), in->rotation.begin(), in->rotation.end());
    out.scale.insert(out.scale.end(), in->scale.begin(), in->scale.end());
    out.class_id.insert(out.class_id.end(), in->class_id.begin(), in->class_id.end());
    for (auto& [attr, values] : out.attributes) values.resize(out.size(), 0.0f);
    for (const auto& [attr, values] : in->attributes) {
      auto& dst = out.attributes[attr];
      dst.resize(base, 0.0f);
      dst.insert(dst.end(), values.begin(), values.end());
    }
  }
  for (auto& [attr, values] : out.attributes) values.resize(out.size(), 0.0f);
  return out;
}

}  // namespace orogen
