#include "nodes/erosion/erosion_common.h"

#include "nodes/common/cancellable_rows.h"

namespace orogen::erosion {

void fill_change_maps(const Heightfield& in, ErosionMaps& maps, const ExecContext* ctx) {
  maps.erosion = std::make_shared<Heightfield>(in.domain);
  maps.deposition = std::make_shared<Heightfield>(in.domain);
  const int w = in.width();
  auto body = [&](int j) {
    for (int i = 0; i < w; ++i) {
      const std::size_t k = in.index(i, j);
      const float d = maps.out->data[k] - in.data[k];
      maps.erosion->data[k] = d < 0 ? -d : 0.0f;
      maps.deposition->data[k] = d > 0 ? d : 0.0f;
    }
  };
  (void)ctx;
  for_each_row(nullptr, in.height(), body);
}

}  // namespace orogen::erosion
