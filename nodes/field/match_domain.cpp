#include "nodes/field/match_domain.h"

#include "nodes/common/resample.h"
#include "nodes/common/cancellable_rows.h"

namespace orogen {

HeightfieldPtr match_domain(HeightfieldPtr field, const Domain& target, const ExecContext* ctx) {
  if (!field || field->domain == target) return field;
  auto out = std::make_shared<Heightfield>(target);
  for_each_row(ctx, target.height(), [&](int j) { resample_bilinear_row(*field, target, j, out->row(j)); });
  return out;
}

}  // namespace orogen
