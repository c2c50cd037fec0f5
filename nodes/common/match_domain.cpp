#include "nodes/common/match_domain.h"

#include <stdexcept>

#include "nodes/common/cancellable_rows.h"
#include "nodes/common/resample.h"

namespace orogen {

HeightfieldPtr match_domain(HeightfieldPtr field, const Domain& target, const ExecContext* ctx) {
  if (!field || field->domain == target) return field;
  auto out = std::make_shared<Heightfield>(target);
  for_each_row(ctx, target.height(), [&](int j) { resample_bilinear_row(*field, target, j, out->row(j)); });
  return out;
}

ImagePtr match_domain(ImagePtr image, const Domain& target, const ExecContext* ctx) {
  if (!image || image->domain == target) return image;
  auto out = std::make_shared<Image>(target, image->channels);
  out->channel_names = image->channel_names;
  out->color = image->color;
  const std::size_t row = static_cast<std::size_t>(target.width()) * static_cast<std::size_t>(image->channels);
  for_each_row(ctx, target.height(), [&](int j) {
    float* first = out->data.data() + row * static_cast<std::size_t>(j);
    resample_bilinear_row(*image, target, j, std::span<float>(first, row));
  });
  return out;
}

bool domains_overlap(const Domain& a, const Domain& b) {
  const glm::dvec2 a0 = a.min_corner(), a1 = a.max_corner(), b0 = b.min_corner(), b1 = b.max_corner();
  return a0.x <= b1.x && b0.x <= a1.x && a0.y <= b1.y && b0.y <= a1.y;
}

std::string no_overlap_message(const ExecContext& ctx, std::string_view port, const Domain& field,
                               const Domain& primary) {
  return ctx.type().name + " '" + ctx.node_id() + "': input '" + std::string(port) + "' (" + field.describe() +
         ") does not overlap the node's grid (" + primary.describe() + "), so it cannot be resampled onto it";
}

void check_overlap(const ExecContext& ctx, std::string_view port, const Domain& field, const Domain& primary) {
  if (!domains_overlap(field, primary)) throw NodeError(no_overlap_message(ctx, port, field, primary));
}

template <class T>
std::shared_ptr<const T> secondary_input(const ExecContext& ctx, std::string_view port, const Domain& primary) {
  auto value = ctx.input<T>(port);
  if (!value || value->domain == primary) return value;
  check_overlap(ctx, port, value->domain, primary);
  return match_domain(std::move(value), primary, &ctx);
}

template <class T>
std::shared_ptr<const T> require_secondary_input(const ExecContext& ctx, std::string_view port, const Domain& primary) {
  ctx.require<T>(port);  // the usual message when nothing is connected
  return secondary_input<T>(ctx, port, primary);
}

template HeightfieldPtr secondary_input<Heightfield>(const ExecContext&, std::string_view, const Domain&);
template ImagePtr secondary_input<Image>(const ExecContext&, std::string_view, const Domain&);
template HeightfieldPtr require_secondary_input<Heightfield>(const ExecContext&, std::string_view, const Domain&);
template ImagePtr require_secondary_input<Image>(const ExecContext&, std::string_view, const Domain&);

HeightfieldPtr world_sampled_input(const ExecContext& ctx, std::string_view port, const Domain& primary) {
  auto value = ctx.input<Heightfield>(port);
  if (value) check_overlap(ctx, port, value->domain, primary);
  return value;
}

void require_same_grid(const Domain& field, const Domain& primary, std::string_view what) {
  if (field.resolution != primary.resolution)
    throw std::invalid_argument(std::string(what) + " (" + field.describe() + ") must lie on the primary grid (" +
                                primary.describe() + "); resample it first (match_domain)");
}

}  // namespace orogen
