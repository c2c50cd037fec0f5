// Plant nodes: LSystem (grammar -> module string), Turtle3D (module string -> skeleton curves and leaf
// points), TreeMesh (skeleton and leaves -> mesh), PlantSprite (module string -> flat 2D plant mesh). Thin
// adapters over lsystem.h, turtle.h, tree_mesh.h, plant_sprite.h.
#include <memory>
#include <stdexcept>
#include <utility>

#include "graph/cost_query.h"
#include "graph/exec_context.h"
#include "graph/mesh.h"
#include "graph/angles.h"
#include "graph/registry.h"
#include "nodes/plants/lsystem.h"
#include "nodes/plants/plant_sprite.h"
#include "nodes/plants/tree_mesh.h"
#include "nodes/plants/turtle.h"

namespace orogen {
namespace {

// Sets the node's mesh output from `build` (a plant mesh builder): its argument errors become node errors,
// and a builder stopped by cancellation leaves no result.
template <class Build>
void set_plant_mesh(ExecContext& ctx, Build&& build) {
  auto mesh = std::make_shared<Mesh>();
  try {
    *mesh = std::forward<Build>(build)();
  } catch (const std::invalid_argument& e) {
    throw NodeError(e.what());
  }
  ctx.check_cancelled();
  ctx.set_output("out", std::move(mesh));
}

}  // namespace

OROGEN_NODE(LSystem) {
  b.distribution(Distribution::Replicated);
  b.reach_global();
  b.domain_independent();
  b.category("plants").description(
      "Derives a word of modules from an axiom and rules in the notation of Prusinkiewicz & Lindenmayer (1990), "
      "The Algorithmic Beauty of Plants: parametric modules F(l,w) with arithmetic expressions, conditions "
      "(A(x) : x < 3 -> ...), left and right context (A < B > C) matched across bracketed branches with an "
      "ignore list, stochastic alternatives chosen by the roulette of their weights (A -> B : 2) as in "
      "S. Ekman et al. (2016), SeamScape (Chalmers bachelor thesis), and random draws uniform(a,b) / gauss(m,s) keyed "
      "by the seed. One "
      "rule per line or separated by ';'; 'let name = value' defines constants; '//' starts a comment line. "
      "Errors name the line and column. Presets (docs/lsystems.md): algae (A -> AB; B -> A), the bush "
      "of ABOP Fig. 1.25, the fern-like plant of ABOP Fig. 1.24d, 3D Game Worlds rules 4.19 and 4.20, and "
      "SeamScape's green tree.");
  b.output("out", PortType::ModuleString).description("The derived word (symbols with parameters)");
  b.param_string("axiom", "X").description("The initial word, e.g. X or T(140,90,40,100)");
  b.param_string("rules", "X -> F[+X][-X]FX\nF -> FF")
      .description("Productions, one per line: [left <] predecessor [> right] [: condition] -> successor [: weight]");
  b.param_int("iterations", 4).unit(Unit::Count).range(0, 40).soft_range(0, 8).description("Parallel rewriting steps");
  b.param_string("ignore", "").description("Symbols that context matching skips (typically the turtle's +-&^\\/F)");
  b.param_seed("seed", 0).description(
      "Key of the stochastic choices and random draws; the same seed gives the same word");
  b.param_int("max_modules", 1000000)
      .unit(Unit::Count)
      .range(1, 100000000)
      .description("A word longer than this fails with an error instead of exhausting memory (modules)");
  // The word may grow to the grammar's bound on its length after the iterations (at most max_modules modules),
  // each with as many parameters as the grammar's widest module.
  b.extra_bytes([](const CostQuery& q) -> std::uint64_t {
    const plants::LSystem l(q.params.get<std::string>("axiom"), q.params.get<std::string>("rules"),
                            q.params.get<std::string>("ignore"));
    const auto max_modules = static_cast<std::uint64_t>(q.params.get<std::int64_t>("max_modules"));
    const std::uint64_t length =
        l.max_word_length(static_cast<int>(q.params.get<std::int64_t>("iterations")), max_modules);
    return plants::derive_peak_bytes(static_cast<std::size_t>(length), l.max_module_parameters());
  });
  b.execute([](ExecContext& ctx) {
    plants::DeriveOptions o;
    o.iterations = static_cast<int>(ctx.param<std::int64_t>("iterations"));
    o.seed = ctx.param<std::uint64_t>("seed");
    o.max_modules = static_cast<std::size_t>(ctx.param<std::int64_t>("max_modules"));
    o.progress = [&ctx](double f) { ctx.progress(f); };
    o.should_stop = [&ctx] { return ctx.cancelled(); };
    auto word = std::make_shared<ModuleString>();
    try {
      const plants::LSystem l(ctx.param<std::string>("axiom"), ctx.param<std::string>("rules"),
                              ctx.param<std::string>("ignore"));
      *word = l.derive(o);
    } catch (const plants::LSystemError& e) {
      throw NodeError(e.what());
    }
    ctx.check_cancelled();
    ctx.set_output("out", std::move(word));
  });
}

OROGEN_NODE(Turtle3D) {
  b.distribution(Distribution::Replicated);
  b.reach_global();
  b.domain_independent();
  b.category("plants").description(
      "Interprets a module string with a 3D turtle (Prusinkiewicz & Lindenmayer 1990, The Algorithmic Beauty of "
      "Plants, ch. 1.5, 2.2): F f move, + - turn, & ^ pitch, \\ / roll, | turn around, $ level, [ ] branch, "
      "#(r,g,b) color, < > ! width, L(size,r,g,b) leaf. The frame (heading, left, up) is re-orthonormalized "
      "after every rotation; tropism bends the heading towards a direction after each F (ABOP eq. 2.5). The "
      "plant grows from the origin along +z, in metres.");
  b.input("in", PortType::ModuleString).description("Word from LSystem");
  b.output("out", PortType::Curves)
      .description(
          "Skeleton: one curve per branch, parent = the branch it grows from; width (m) and attributes r, g, b "
          "(linear color) and depth (branching depth) per point");
  b.output("leaves", PortType::Points)
      .description(
          "Leaves: position, rotation (x = heading, y = left, z = up), scale = size (m), attributes r, g, b, branch");
  b.param_float("step", 1.0)
      .range(0.0, 1000.0)
      .soft_range(0.01, 10.0)
      .unit(Unit::Metre)
      .description("Length of F and f without a parameter");
  b.param_float("angle", 25.0)
      .range(-360.0, 360.0)
      .soft_range(0.0, 90.0)
      .unit(Unit::Degree)
      .description("Rotation of + - & ^ \\ / without a parameter");
  b.param_float("width", 0.1)
      .range(0.0, 100.0)
      .soft_range(0.0, 2.0)
      .unit(Unit::Metre)
      .description("Initial branch width (diameter)");
  b.param_float("width_factor", 0.7)
      .range(0.01, 1.0)
      .unit(Unit::Factor)
      .description("> multiplies and < divides the width by this when they have no parameter");
  b.param_vec3("tropism", {0.0, 0.0, -1.0})
      .range(-1.0, 1.0)
      .unit(Unit::Unitless)
      .description("Direction the branches bend towards (gravity: 0, 0, -1)");
  b.param_float("tropism_strength", 0.0)
      .range(-60.0, 60.0)
      .soft_range(0.0, 30.0)
      .unit(Unit::Degree)
      .description(
          "Susceptibility e: each F turns the heading by e |H x T| degrees towards the tropism direction (ABOP's e "
          "= 0.1 is 5.73 here)");
  b.param_color("color", {0.35f, 0.22f, 0.12f, 1.0f}).description("Initial branch color (linear RGB)");
  b.param_float("leaf_size", 0.2)
      .range(0.0, 100.0)
      .soft_range(0.0, 2.0)
      .unit(Unit::Metre)
      .description("Size of L without a parameter");
  b.param_color("leaf_color", {0.1f, 0.35f, 0.05f, 1.0f})
      .description("Color of L without color parameters (linear RGB)");
  // A skeleton point or a leaf per module at most, with the turtle stack: about 64 bytes a module
  // (measured: tests/test_peak_memory.cpp).
  b.extra_bytes([](const CostQuery& q) -> std::uint64_t {
    const PortValue* in = q.input("in");
    return in ? per_item_bytes(static_cast<double>(std::get<ModuleStringPtr>(*in)->size()), 64.0) : 0;
  });
  b.execute([](ExecContext& ctx) {
    const auto word = ctx.require<ModuleString>("in");
    plants::TurtleOptions o;
    o.step = ctx.param<double>("step");
    o.angle = ctx.param<double>("angle");
    o.width = ctx.param<double>("width");
    o.width_factor = ctx.param<double>("width_factor");
    o.tropism = ctx.param<glm::dvec3>("tropism");
    o.tropism_strength = radians_from_degrees(ctx.param<double>("tropism_strength"));
    const glm::vec4 c = ctx.param<glm::vec4>("color"), lc = ctx.param<glm::vec4>("leaf_color");
    o.color = glm::dvec3(c.r, c.g, c.b);
    o.leaf_size = ctx.param<double>("leaf_size");
    o.leaf_color = glm::dvec3(lc.r, lc.g, lc.b);
    o.should_stop = [&ctx] { return ctx.cancelled(); };
    auto r = plants::interpret(*word, o);
    ctx.check_cancelled();
    ctx.set_output("out", std::make_shared<Curves>(std::move(r.skeleton)));
    ctx.set_output("leaves", std::make_shared<Points>(std::move(r.leaves)));
  });
}

OROGEN_NODE(TreeMesh) {
  b.distribution(Distribution::Replicated);
  b.reach_global();
  b.domain_independent();
  b.category("plants").description(
      "Meshes a plant skeleton as generalized cylinders (Bloomenthal 1985, Modeling the mighty maple; "
      "Prusinkiewicz, Lindenmayer & Hanan 1988): a ring of k vertices at each point of each branch in a "
      "rotation-minimizing frame, radius and color interpolated along the branch, both ends capped, so every "
      "branch is a closed surface; children start on their parent's axis, hiding the joint. Leaves become "
      "small diamond quads or closed hull rocks (S. Ekman et al. 2016, SeamScape). Texture coordinates run around (u) "
      "and "
      "along (v, metres) each branch. Over the triangle budget the sides shrink first (down to 3), then the "
      "thinnest twigs and their leaves are dropped.");
  b.input("in", PortType::Curves).description("Skeleton from Turtle3D (width = diameter, m; colors r, g, b)");
  b.input("leaves", PortType::Points).optional().description("Leaves from Turtle3D");
  b.output("out", PortType::Mesh).description("The plant mesh, metres, z up");
  b.param_int("sides", 8).unit(Unit::Count).range(3, 64).description("Vertices around each branch (k)");
  b.param_int("max_triangles", 200000)
      .unit(Unit::Count)
      .range(16, 50000000)
      .description("Triangle budget for branches and leaves together");
  b.param_enum("leaf_shape", {"none", "quad", "rock"}, "quad")
      .description("Leaves as nothing, one-sided diamond quads (2 triangles) or closed convex hulls of 8 points");
  b.param_seed("seed", 0).description("Key of the rock leaves' shapes");
  b.extra_bytes([](const CostQuery& q) -> std::uint64_t {
    // A tube of `sides` quads per skeleton segment and two triangles a leaf, at most max_triangles, about
    // 224 bytes a triangle with its vertices, half-edges and attributes in OpenMesh (measured:
    // tests/test_peak_memory.cpp).
    const PortValue* in = q.input("in");
    if (!in) return per_item_bytes(static_cast<double>(q.params.get<std::int64_t>("max_triangles")), 224.0);
    const PortValue* leaves = q.input("leaves");
    const double segments = static_cast<double>(std::get<CurvesPtr>(*in)->vertex_count());
    const double leaf_count = leaves ? static_cast<double>(std::get<PointsPtr>(*leaves)->size()) : 0.0;
    const double triangles =
        std::min(2.0 * segments * static_cast<double>(q.params.get<std::int64_t>("sides")) + 2.0 * leaf_count,
                 static_cast<double>(q.params.get<std::int64_t>("max_triangles")));
    return per_item_bytes(triangles, 224.0);
  });
  b.execute([](ExecContext& ctx) {
    const auto skeleton = ctx.require<Curves>("in");
    const auto leaves = ctx.input<Points>("leaves");
    plants::TreeMeshOptions o;
    o.sides = static_cast<int>(ctx.param<std::int64_t>("sides"));
    o.max_triangles = static_cast<std::size_t>(ctx.param<std::int64_t>("max_triangles"));
    o.leaf_shape = static_cast<plants::LeafShape>(ctx.enum_index("leaf_shape"));
    o.seed = ctx.param<std::uint64_t>("seed");
    o.should_stop = [&ctx] { return ctx.cancelled(); };
    set_plant_mesh(ctx, [&] { return plants::tree_mesh(*skeleton, leaves.get(), o); });
  });
}

OROGEN_NODE(PlantSprite) {
  b.distribution(Distribution::Replicated);
  b.reach_global();
  b.domain_independent();
  b.category("plants").description(
      "A flat plant from an L-system word, drawn by a 2D turtle (Prusinkiewicz & Lindenmayer 1990, The "
      "Algorithmic Beauty of Plants, ch. 1: F draws, f moves, + and - turn, | turns around, [ ] branch, ! sets "
      "the width) in the vertical x-z plane: every segment a ribbon quad of the branch's width, narrowed by "
      "taper per branch level, every leaf symbol a small diamond quad along the heading. crossed repeats the "
      "drawing in the y-z plane (two crossed billboards, readable from every side). The mesh stands on its "
      "root: its lowest point is at z = 0, so Instance places it on the ground. 3D turtle symbols are ignored.");
  b.input("in", PortType::ModuleString).description("Word from LSystem");
  b.output("out", PortType::Mesh).description("The flat plant mesh, metres, z up, base at z = 0");
  b.param_float("step", 0.1)
      .range(0.0, 1000.0)
      .soft_range(0.01, 2.0)
      .unit(Unit::Metre)
      .description("Segment length of F and f without a parameter, metres");
  b.param_float("angle", 25.0)
      .range(-360.0, 360.0)
      .soft_range(0.0, 90.0)
      .unit(Unit::Degree)
      .description("Turn of + and - without a parameter, degrees");
  b.param_float("width", 0.05)
      .range(0.0, 100.0)
      .soft_range(0.0, 1.0)
      .unit(Unit::Metre)
      .description("Ribbon width of the trunk (branch level 0), metres");
  b.param_float("taper", 0.7)
      .range(0.0, 1.0)
      .unit(Unit::Factor)
      .description("Width factor per branch level: a branch opened by [ is taper times as wide as its parent");
  b.param_enum("planes", {"single", "crossed"}, "crossed")
      .description("single: the drawing in the x-z plane only; crossed: also in the y-z plane (a billboard cross)");
  b.param_string("leaf_symbol", "L")
      .description(
          "The symbol drawn as a leaf (one character; empty: none), e.g. L placed at the branch tips by the rules; "
          "its first parameter is the leaf length in metres");
  b.param_float("leaf_size", 0.15)
      .range(0.0, 100.0)
      .soft_range(0.0, 1.0)
      .unit(Unit::Metre)
      .description("Leaf length without a parameter, metres; the leaf is half as wide");
  b.param_color("color", {0.30f, 0.20f, 0.10f, 1.0f}).description("Stem color (linear RGB)");
  b.param_color("leaf_color", {0.10f, 0.35f, 0.05f, 1.0f}).description("Leaf color (linear RGB)");
  b.param_int("max_triangles", 2000000)
      .unit(Unit::Count)
      .range(16, 50000000)
      .description("Triangle budget (2 per segment or leaf per plane); a larger plant is an error");
  // Up to two planes of one quad per module of the word, with OpenMesh's tables: about 512 bytes a module
  // (measured: tests/test_peak_memory.cpp).
  b.extra_bytes([](const CostQuery& q) -> std::uint64_t {
    const PortValue* in = q.input("in");
    return in ? per_item_bytes(static_cast<double>(std::get<ModuleStringPtr>(*in)->size()), 512.0) : 0;
  });
  b.execute([](ExecContext& ctx) {
    const auto word = ctx.require<ModuleString>("in");
    plants::PlantSpriteOptions o;
    o.step = ctx.param<double>("step");
    o.angle = ctx.param<double>("angle");
    o.width = ctx.param<double>("width");
    o.taper = ctx.param<double>("taper");
    o.crossed = ctx.param<std::string>("planes") == "crossed";
    const std::string& leaf = ctx.param<std::string>("leaf_symbol");
    if (leaf.size() > 1) throw NodeError("leaf_symbol must be one character or empty, found '" + leaf + "'");
    o.leaf_symbol = leaf.empty() ? '\0' : leaf[0];
    o.leaf_size = ctx.param<double>("leaf_size");
    o.color = ctx.param<glm::vec4>("color");
    o.leaf_color = ctx.param<glm::vec4>("leaf_color");
    o.max_triangles = static_cast<std::size_t>(ctx.param<std::int64_t>("max_triangles"));
    o.should_stop = [&ctx] { return ctx.cancelled(); };
    set_plant_mesh(ctx, [&] { return plants::plant_sprite(*word, o); });
  });
}

}  // namespace orogen
