#include "nodes/landform/canyon.h"

#include <algorithm>
#include <limits>
#include <cmath>
#include <numbers>

#include "graph/cost_query.h"
#include "graph/registry.h"
#include "graph/table_json.h"
#include "nodes/common/cancellable_rows.h"
#include "nodes/common/hash.h"
#include "nodes/common/smoothstep.h"
#include "nodes/landform/landform_common.h"

namespace orogen {

using landform::num;
using landform::require;

namespace {
constexpr int kMeanderOctaves = 3;
constexpr std::size_t kMaxPathPoints = 256;

// The path's segments of non-zero length, with the distance along the path at each one's start.
struct Segment {
  glm::dvec2 a, dir;  // start, unit direction
  double length, along;
};

std::vector<Segment> segments_of(const std::vector<glm::dvec2>& path) {
  std::vector<Segment> out;
  double along = 0.0;
  for (std::size_t k = 0; k + 1 < path.size(); ++k) {
    const glm::dvec2 d = path[k + 1] - path[k];
    const double length = std::hypot(d.x, d.y);
    if (!(length > 0.0)) continue;  // a repeated point
    out.push_back({path[k], d / length, length, along});
    along += length;
  }
  return out;
}

// Distance from (x, y) to the path and the distance along the path of the nearest point.
void nearest_on_path(const std::vector<Segment>& path, double x, double y, double& distance, double& along) {
  distance = std::numeric_limits<double>::infinity();
  along = 0.0;
  for (const Segment& g : path) {
    const double t = std::clamp((x - g.a.x) * g.dir.x + (y - g.a.y) * g.dir.y, 0.0, g.length);
    const double d = std::hypot(x - (g.a.x + g.dir.x * t), y - (g.a.y + g.dir.y * t));
    if (d < distance) distance = d, along = g.along + t;
  }
}

double canyon_offset(const CanyonParams& p, const std::vector<Segment>& path, double total, double x, double y) {
  double d = 0.0, s = 0.0;
  nearest_on_path(path, x, y, d, s);
  const double a = p.taper_length > 0.0 ? smoothstep01(std::min(s, total - s) / p.taper_length) : 1.0;
  const double depth = p.depth * a;
  const double half_floor = 0.5 * p.floor_width;
  if (d <= half_floor) return -depth;
  const double a_rad = p.wall_slope * std::numbers::pi / 180.0;
  const double wall = depth * std::cos(a_rad) / std::sin(a_rad);  // depth / tan: exact at 45 degrees
  if (!(d < half_floor + wall)) return 0.0;
  double f = (d - half_floor) / wall;
  if (p.terraces > 0) {
    const double n = static_cast<double>(p.terraces);
    const double k = std::min(std::floor(f * n), n - 1.0);
    const double g = f * n - k;
    f = (k + std::max(0.0, 2.0 * g - 1.0)) / n;
  }
  return -depth * (1.0 - f);
}

TableSchema path_schema() {
  TableSchema s;
  s.min_rows = 2;
  s.max_rows = kMaxPathPoints;
  s.add("x", ColumnType::Number).range(-1e7, 1e7).unit_of(Unit::Metre).describe("World x of the point");
  s.add("y", ColumnType::Number).range(-1e7, 1e7).unit_of(Unit::Metre).describe("World y of the point");
  return s;
}

TableValue default_path() {
  return table_from_json_text(R"([{"x": 100, "y": 700}, {"x": 480, "y": 580}, {"x": 924, "y": 300}])", path_schema());
}
}  // namespace

void check_canyon(const CanyonParams& p) {
  require(p.path.size() >= 2 && p.path.size() <= kMaxPathPoints, "Canyon",
          "path has " + num(static_cast<double>(p.path.size())) + " points; it needs 2 to " + num(kMaxPathPoints));
  require(!segments_of(p.path).empty(), "Canyon",
          "every point of path is the same (" + num(p.path[0].x) + ", " + num(p.path[0].y) +
              ") m; a canyon needs a length");
  require(p.depth >= 0.0, "Canyon", "depth (" + num(p.depth) + " m) must be at least 0");
  require(p.floor_width >= 0.0, "Canyon", "floor_width (" + num(p.floor_width) + " m) must be at least 0");
  require(p.wall_slope > 0.0 && p.wall_slope < 90.0, "Canyon",
          "wall_slope (" + num(p.wall_slope) + " deg) must be above 0 and below 90");
  require(p.terraces >= 0, "Canyon", "terraces (" + num(p.terraces) + ") must be at least 0");
  require(p.taper_length >= 0.0, "Canyon", "taper_length (" + num(p.taper_length) + " m) must be at least 0");
  require(p.meander >= 0.0, "Canyon", "meander (" + num(p.meander) + " m) must be at least 0");
  require(p.meander_feature_size > 0.0, "Canyon",
          "meander_feature_size (" + num(p.meander_feature_size) + " m) must be positive");
}

std::shared_ptr<Heightfield> canyon_field(const Domain& domain, const CanyonParams& p, const ExecContext* ctx) {
  check_canyon(p);
  const auto path = segments_of(p.path);
  const double total = path.back().along + path.back().length;
  Heightfield wx, wy;
  if (p.meander > 0.0) {
    wx = landform::unit_noise(domain, p.meander_feature_size, kMeanderOctaves, false, p.seed, ctx);
    wy = landform::unit_noise(domain, p.meander_feature_size, kMeanderOctaves, false, hash64(p.seed, 1), ctx);
  }
  auto out = std::make_shared<Heightfield>(domain);
  for_each_row(ctx, domain.height(), [&](int j) {
    const double y = domain.y(j);
    auto o = out->row(j);
    for (int i = 0; i < domain.width(); ++i) {
      double qx = domain.x(i), qy = y;
      if (p.meander > 0.0) {
        qx += p.meander * static_cast<double>(wx.at(i, j));
        qy += p.meander * static_cast<double>(wy.at(i, j));
      }
      o[static_cast<std::size_t>(i)] = static_cast<float>(canyon_offset(p, path, total, qx, qy));
    }
  });
  return out;
}

OROGEN_NODE(Canyon) {
  b.reach_pointwise();
  // The noise fields held beside the output while it is filled.
  b.extra_bytes(
      [](const CostQuery& q) { return per_sample_bytes(q, q.params.get<double>("meander") > 0.0 ? 8.0 : 0.0); });
  b.category("landform")
      .description(
          "A canyon cut along the polyline `path`, as a height offset (0 away from it, -depth on its floor) to Add "
          "to a terrain (the Min of several canyons is a branching one): a flat floor floor_width wide, "
          "walls at wall_slope (optionally in `terraces` steps, "
          "each a flat bench and a riser twice as steep, like the stepped walls of canyons cut through layered "
          "rock), the depth tapering to 0 over taper_length at each end, and the path meandering by up to "
          "`meander` (the sample displaced by seeded fBm, K. Perlin (2002), \"Improving noise\", SIGGRAPH).");
  b.output("out", PortType::Heightfield)
      .description("Height offset, metres (<= 0): add it to a terrain")
      .kind(OutputKind::Signed)
      .unit(Unit::Metre);
  b.param_table("path", path_schema(), default_path())
      .description("The points the canyon runs through, in order (2 to 256; x, y in metres)");
  b.param_float("depth", 120.0)
      .range(0.0, 1e5)
      .soft_range(0.0, 2000.0)
      .unit(Unit::Metre)
      .description("Depth of the floor below the surrounding terrain");
  b.param_float("floor_width", 40.0)
      .range(0.0, 1e7)
      .soft_range(0.0, 2000.0)
      .unit(Unit::Metre)
      .description("Width of the flat floor");
  b.param_float("wall_slope", 55.0)
      .range(1.0, 89.0)
      .unit(Unit::Degree)
      .description("Mean steepness of the walls (of each step's bench and riser together when terraced)");
  b.param_int("terraces", 0)
      .range(0, 50)
      .unit(Unit::Count)
      .description("Steps in each wall, each a flat bench and a riser; 0 for smooth walls");
  b.param_float("taper_length", 100.0)
      .range(0.0, 1e7)
      .soft_range(0.0, 5000.0)
      .unit(Unit::Metre)
      .description("Length over which the depth comes up to 0 at each end; 0 for full depth to the ends");
  b.param_float("meander", 60.0)
      .range(0.0, 1e6)
      .soft_range(0.0, 1000.0)
      .unit(Unit::Metre)
      .description("How far the path wanders from the polyline; 0 to follow it exactly");
  b.param_float("meander_feature_size", 400.0)
      .range(1e-3, 1e7)
      .soft_range(20.0, 5000.0)
      .unit(Unit::Metre)
      .description("Length of the largest bends");
  b.param_seed("seed", 0).description("Random seed of the meanders");
  b.execute([](ExecContext& ctx) {
    CanyonParams p;
    p.path.clear();
    for (const auto& row : ctx.param<TableValue>("path").rows)
      p.path.push_back({std::get<double>(row[0]), std::get<double>(row[1])});
    p.depth = ctx.param<double>("depth");
    p.floor_width = ctx.param<double>("floor_width");
    p.wall_slope = ctx.param<double>("wall_slope");
    p.terraces = static_cast<int>(ctx.param<std::int64_t>("terraces"));
    p.taper_length = ctx.param<double>("taper_length");
    p.meander = ctx.param<double>("meander");
    p.meander_feature_size = ctx.param<double>("meander_feature_size");
    p.seed = ctx.param<std::uint64_t>("seed");
    ctx.set_output("out", canyon_field(ctx.domain(), p, &ctx));
  });
}

}  // namespace orogen
