// Plants: L-system derivation (ABOP reference words, context across brackets, parametric and conditional
// rules, stochastic determinism and weight distribution, grammar errors with positions), the 3D turtle
// (orthonormal frame, known end points, bracket return, tropism) and tree meshes (closed per branch,
// consistent winding, triangle budget), and flat 2D plant sprites (counts per symbol, standing on z = 0,
// analytic heights, determinism).
#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <set>
#include <string>

#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <glm/geometric.hpp>

#include "evaluator/run_node.h"
#include "evaluator/value_serialization.h"
#include "graph/exec_context.h"
#include "graph/mesh.h"
#include "graph/module_string.h"
#include "graph/scene.h"
#include "nodes/io/mesh_file.h"
#include "nodes/plants/lsystem.h"
#include "nodes/plants/plant_sprite.h"
#include "nodes/plants/tree_mesh.h"
#include "nodes/plants/turtle.h"
#include "support/key_checks.h"
#include "support/test_paths.h"

namespace orogen::plants {
namespace {

TEST(LSystem, AlgaeSequence) {
  const char* expected[] = {"A", "AB", "ABA", "ABAAB", "ABAABABA", "ABAABABAABAAB"};
  for (int n = 0; n < 6; ++n) EXPECT_EQ(derive_text("A", "A -> AB\nB -> A", n), expected[n]) << n;
}

TEST(LSystem, Rules419And420SymbolCounts) {
  // 3D Game Worlds (Al Akhawayn 2022) rules 4.19 and 4.20 with ABOP's F -> FF; typographic minus accepted.
  const LSystem a("X", "X \u2192 [FF[+XF\u2212F+FX]\u2212\u2212F+F\u2212FX]\nF \u2192 FF");
  DeriveOptions o;
  o.iterations = 3;
  EXPECT_EQ(a.derive(o).size(), 322u);
  const LSystem b("X", "X -> F-[[X]+X]+F[+FX]-X; F -> FF");
  o.iterations = 4;
  EXPECT_EQ(b.derive(o).size(), 1551u);
}

TEST(LSystem, KochCurveMatchesStringRewriting) {
  // ABOP Fig. 1.9b quadratic Koch island rule, checked against plain string substitution.
  std::string ref = "F-F-F-F";
  for (int k = 0; k < 3; ++k) {
    std::string next;
    for (char c : ref) next += c == 'F' ? std::string("F+FF-FF-F-F+F+FF-F-F+F+FF+FF-F") : std::string(1, c);
    ref = next;
  }
  EXPECT_EQ(derive_text("F-F-F-F", "F -> F+FF-FF-F-F+F+FF-F-F+F+FF+FF-F", 3), ref);
}

TEST(LSystem, ParametricRulesAndConditions) {
  // ABOP p. 43, parametric example: A(x,y) : y <= 3 -> A(x*2, x+y); A(x,y) : y > 3 -> B(x) A(x/y, 0);
  // B(x) : x < 1 -> C; B(x) : x >= 1 -> B(x-1).
  const std::string rules =
      "A(x,y) : y <= 3 -> A(x*2,x+y)\n"
      "A(x,y) : y > 3 -> B(x)A(x/y,0)\n"
      "B(x) : x < 1 -> C\n"
      "B(x) : x >= 1 -> B(x-1)\n";
  EXPECT_EQ(derive_text("B(2)A(4,4)", rules, 1), "B(1)B(4)A(1,0)");
  EXPECT_EQ(derive_text("B(2)A(4,4)", rules, 2), "B(0)B(3)A(2,1)");
  EXPECT_EQ(derive_text("B(2)A(4,4)", rules, 3), "CB(2)A(4,3)");
  EXPECT_EQ(derive_text("B(2)A(4,4)", rules, 4), "CB(1)A(8,7)");
  EXPECT_EQ(derive_text("B(2)A(4,4)", rules, 5), "CB(0)B(8)A(1.1428572,0)");
}

TEST(LSystem, ExpressionsAndConstants) {
  EXPECT_EQ(derive_text("A(2)", "let k = 3; A(x) -> B(x^2*k, -x + 10 / 4, max(x, 7), (x > 1) && (x < 3), cos(60))", 1),
            "B(12,0.5,7,1,0.5)");
  // A parameter count mismatch: the rule does not apply.
  EXPECT_EQ(derive_text("A(1,2)", "A(x) -> B", 1), "A(1,2)");
}

TEST(LSystem, LeftContextSkipsBracketedBranches) {
  // The left context of a module is its ancestor on the path to the root: a ']' before it skips the sibling
  // branch, a '[' steps out to the parent. (Tools that compare with the previous symbol of the text get
  // both cases wrong.)
  EXPECT_EQ(derive_text("A[C]B", "A < B -> X", 1), "A[C]X");  // sibling branch skipped
  EXPECT_EQ(derive_text("A[B]", "A < B -> X", 1), "A[X]");    // branch start: parent is A
  EXPECT_EQ(derive_text("C[A]B", "A < B -> X", 1), "C[A]B");  // A is in a sibling branch, not an ancestor
  EXPECT_EQ(derive_text("A[C][D]B", "A < B -> X", 1), "A[C][D]X");
  EXPECT_EQ(derive_text("AF+B", "A < B -> X", 1), "AF+B");  // F and + are modules unless ignored
  EXPECT_EQ(derive_text("AF+B", "A < B -> X", 1, 0, "F+"), "AF+X");
}

TEST(LSystem, RightContextSkipsBranchesAndMatchesBracketPatterns) {
  EXPECT_EQ(derive_text("A[C]B", "A > B -> X", 1), "X[C]B");           // branch between skipped
  EXPECT_EQ(derive_text("[A]B", "A > B -> X", 1), "[A]B");             // end of branch: no successor
  EXPECT_EQ(derive_text("A[C]B", "A > [C]B -> X", 1), "X[C]B");        // bracketed pattern
  EXPECT_EQ(derive_text("A[D][C]B", "A > [C]B -> X", 1), "X[D][C]B");  // any of the branches
  EXPECT_EQ(derive_text("A[D]B", "A > [C]B -> X", 1), "A[D]B");
  // ABOP p. 32: S < ... the example string and context S > G[H]M.
  EXPECT_EQ(derive_text("ABC[DE][SG[HI[JK]L]MNO]", "S > G[H]M -> X", 1), "ABC[DE][XG[HI[JK]L]MNO]");
  EXPECT_EQ(derive_text("ABC[DE][SG[HI[JK]L]MNO]", "BC < S -> X", 1), "ABC[DE][XG[HI[JK]L]MNO]");
}

TEST(LSystem, AcropetalSignalAlongBrackets) {
  // ABOP Fig. 1.31a style signal propagation with an ignore list: b travels up the main axis and into
  // branches, one module per step.
  const std::string rules = "b < a -> b\nb -> a";
  const std::string ignore = "+-F";
  EXPECT_EQ(derive_text("Fb[+Fa]Fa[-Fa]Fa", rules, 1, 0, ignore), "Fa[+Fb]Fb[-Fa]Fa");
  EXPECT_EQ(derive_text("Fb[+Fa]Fa[-Fa]Fa", rules, 2, 0, ignore), "Fa[+Fa]Fa[-Fb]Fb");
  EXPECT_EQ(derive_text("Fb[+Fa]Fa[-Fa]Fa", rules, 3, 0, ignore), "Fa[+Fa]Fa[-Fa]Fa");
}

TEST(LSystem, ContextRulesTakePrecedence) {
  EXPECT_EQ(derive_text("ABAB", "A < B -> X\nB -> Y", 1), "AXAX");
  EXPECT_EQ(derive_text("CB", "A < B -> X\nB -> Y", 1), "CY");
}

TEST(LSystem, StochasticSameSeedSameWordOtherSeedOther) {
  const std::string rules = "F -> F[+F]F : 1\nF -> F[-F]F : 1\nF -> FF : 1";
  const std::string a = derive_text("F", rules, 4, 7), b = derive_text("F", rules, 4, 7),
                    c = derive_text("F", rules, 4, 8);
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
  // Random draws in parameters too.
  const std::string r = "A -> B(uniform(0, 1)) A";
  EXPECT_EQ(derive_text("A", r, 5, 1), derive_text("A", r, 5, 1));
  EXPECT_NE(derive_text("A", r, 5, 1), derive_text("A", r, 5, 2));
}

TEST(LSystem, PlannedRulesMatchTheGeneralPath) {
  // Rules without context or condition and with constant weights skip per-module matching (a constant successor is
  // copied as a block); a dead conditional rule for the same symbol sends every module down the general path. The
  // words must be the same, parameters and random draws included.
  struct Case {
    const char* axiom;
    const char* rules;
    const char* dead;  // never applies, but makes its symbol's rules general
  };
  const Case cases[] = {
      {"X", "X -> F-[[X]+X]+F[+FX]-X; F -> FF", "F : 0 -> Q; X : 0 -> Q"},
      {"F", "F -> F[+F]F : 1; F -> F[-F]F : 2; F -> FF : 0.5; F -> G : 0", "F : 0 -> Q"},
      {"A(1)B", "A(x) -> A(x*1.5)[+(25)B(x,2)]G(U(0,1)); B -> BF(0.5,2); F(a,b) -> F(a*2,b)",
       "A(x) : 0 -> Q; B : 0 -> Q"},
      {"A(1)A(2,3)AB", "A(x) -> A(x+1)C(7); B -> D(1,2,3)B", "A(x) : 0 -> Q; B : 0 -> Q"},  // other arities: copied
      {"A", "A -> AB : 3; A -> B(uniform(0, 1)) : 1; B -> ", "A : 0 -> Q; B : 0 -> Q"},     // an empty successor
  };
  for (const Case& c : cases)
    for (int n = 0; n <= 6; ++n) {
      for (std::uint64_t seed : {0u, 5u}) {
        const std::string planned = derive_text(c.axiom, c.rules, n, seed);
        EXPECT_EQ(planned, derive_text(c.axiom, std::string(c.rules) + "; " + c.dead, n, seed))
            << c.rules << ", " << n << " steps, seed " << seed;
        if (n == 6) {
          EXPECT_NE(planned, c.axiom) << c.rules;  // the rules do rewrite
        }
      }
    }
}

TEST(LSystem, ReusedBuffersGiveTheSameWord) {
  // A caller keeps the word and its spare between derivations: what they held before must not leak into the next
  // word (a longer word with parameters first, then shorter ones, then a step into a used word).
  const LSystem big("T(140,90,40,100)",
                    "T(r,g,b,a) -> F(0.5,1)[+(U(-30,30))T(r,g,b,0.99*a)]T(r,g,b,a*0.9); F(d,n) -> F(1.7*d,n)");
  const LSystem small("X", "X -> F[+X][-X]FX; F -> FF");
  DeriveOptions o;
  o.seed = 3;
  ModuleString word, spare;
  o.iterations = 7;
  big.derive(o, word, spare);
  EXPECT_EQ(word.text(), big.derive(o).text());
  EXPECT_GT(word.size(), 500u);
  for (int n : {3, 1, 0, 4}) {
    o.iterations = n;
    small.derive(o, word, spare);
    word.check_consistent();
    EXPECT_EQ(word.text(), small.derive(o).text()) << n;
    EXPECT_EQ(word.text(), derive_text("X", "X -> F[+X][-X]FX; F -> FF", n)) << n;
  }
  ModuleString out = big.derive(o);
  small.step(word, out, 4, 3);
  out.check_consistent();
  EXPECT_EQ(out.text(), small.step(word, 4, 3).text());
}

TEST(LSystem, StochasticChoiceFollowsWeights) {
  // 20000 independent modules choose among weights 1 : 3 : 6.
  const LSystem l("A", "A -> X : 1; A -> Y : 3; A -> Z : 6");
  ModuleString w;
  for (int k = 0; k < 20000; ++k) w.append('A');
  const ModuleString out = l.step(w, 0, 42);
  std::map<char, int> count;
  for (char c : out.symbols) ++count[c];
  // Binomial standard deviations: sqrt(n p (1-p)) ~ 42, 65, 69; allow 5 sigma.
  EXPECT_NEAR(count['X'], 2000, 212);
  EXPECT_NEAR(count['Y'], 6000, 324);
  EXPECT_NEAR(count['Z'], 12000, 346);
  // Weight 0 never chosen; a condition excludes.
  const ModuleString none = LSystem("A", "A -> X : 0; A -> Y : 1").step(w, 0, 3);
  EXPECT_EQ(std::count(none.symbols.begin(), none.symbols.end(), 'X'), 0);
}

TEST(LSystem, UniformDrawsStayInRangeAndSpread) {
  const LSystem l("A", "A -> B(uniform(-30, 30))");
  ModuleString w;
  for (int k = 0; k < 5000; ++k) w.append('A');
  const ModuleString out = l.step(w, 0, 9);
  double lo = 1e9, hi = -1e9, sum = 0.0;
  for (float v : out.params) lo = std::min<double>(lo, v), hi = std::max<double>(hi, v), sum += v;
  EXPECT_GE(lo, -30.0);
  EXPECT_LT(hi, 30.0);
  EXPECT_LT(lo, -29.0);
  EXPECT_GT(hi, 29.0);
  EXPECT_NEAR(sum / 5000.0, 0.0, 1.5);  // sd of the mean ~ 0.25
}

TEST(LSystem, SizeBoundFailsClearly) {
  const LSystem l("A", "A -> AA");
  DeriveOptions o;
  o.iterations = 30;
  o.max_modules = 1000;
  try {
    l.derive(o);
    FAIL() << "no error";
  } catch (const LSystemError& e) {
    EXPECT_NE(std::string(e.what()).find("max_modules"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("iteration 10"), std::string::npos) << e.what();
  }
}

struct BadGrammar {
  const char* axiom;
  const char* rules;
  int line, column;
  const char* words;  // part of the message
};

TEST(LSystem, GrammarErrorsGivePosition) {
  const BadGrammar cases[] = {
      {"A", "A -> B\nA BC", 2, 1, "'->' expected"},
      {"A", "A -> B(x)", 1, 8, "unknown name 'x'"},
      {"A", "A(x) -> B(x +)", 1, 14, "expression expected"},
      {"A", "A(x) -> B(foo(x))", 1, 11, "unknown function 'foo'"},
      {"A", "A(x, x) -> B", 1, 6, "appears twice"},
      {"A", "A -> B[C", 1, 5, "'[' without ']'"},
      {"A", "AB -> C", 1, 1, "single module"},
      {"A", "A -> B(1,2", 1, 7, "unbalanced '('"},
      {"A", "A : -> B", 1, 4, "condition expected"},
      {"A", "A -> B : -1", 1, 9, "weight must be >= 0"},
      {"A", "X < -> B", 1, 5, "predecessor expected"},
      {"", "A -> B", 0, 1, "axiom is empty"},
      {"A(1", "A -> B", 0, 2, "unbalanced '('"},
  };
  for (const auto& c : cases) {
    try {
      LSystem l(c.axiom, c.rules);
      ADD_FAILURE() << "no error for " << c.rules;
    } catch (const LSystemError& e) {
      EXPECT_EQ(e.line, c.line) << c.rules << ": " << e.what();
      EXPECT_EQ(e.column, c.column) << c.rules << ": " << e.what();
      EXPECT_NE(std::string(e.what()).find(c.words), std::string::npos) << c.rules << ": " << e.what();
    }
  }
}

TEST(LSystem, CommentsAndBlankLines) { EXPECT_EQ(derive_text("A", "// algae\n\n  A -> AB ; B -> A\n", 2), "ABA"); }

TEST(LSystem, ModuleStringRoundTripsThroughSerialization) {
  const LSystem l("A(1)", "A(x) -> A(x+0.5)[+B(x, 2)]");
  DeriveOptions o;
  const ModuleString w = l.derive(o);
  const PortValue back =
      deserialize_value(serialize_value(PortValue(ModuleStringPtr(std::make_shared<ModuleString>(w)))));
  ASSERT_EQ(port_type_of(back), PortType::ModuleString);
  EXPECT_EQ(std::get<ModuleStringPtr>(back)->text(), w.text());
  EXPECT_EQ(w.text(), "A(2.5)[+B(2,2)][+B(1.5,2)][+B(1,2)]");
}

// --- turtle ------------------------------------------------------------------------------------------------

ModuleString word(const std::string& axiom) { return LSystem(axiom, "").axiom(0); }

void expect_near(const glm::dvec3& a, const glm::dvec3& b, double tol = 1e-6) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

TEST(Turtle, KnownEndPositions) {
  TurtleOptions o;
  o.angle = 90.0;
  // Start at the origin heading +z with left = -x and up = -y.
  expect_near(interpret(word("F+F"), o).final_frame.position, {-1, 0, 1});
  expect_near(interpret(word("F-F"), o).final_frame.position, {1, 0, 1});
  expect_near(interpret(word("FF&F"), o).final_frame.position, {0, 1, 2});  // pitch down: towards -up
  expect_near(interpret(word("FF^F"), o).final_frame.position, {0, -1, 2});
  expect_near(interpret(word("\\(90)+F"), o).final_frame.position, {0, -1, 0});  // roll left: left -> up
  expect_near(interpret(word("F(2.5)|F"), o).final_frame.position, {0, 0, 1.5});
  expect_near(interpret(word("f(3)F(0.5)"), o).final_frame.position, {0, 0, 3.5});
  // A square closes.
  expect_near(interpret(word("F+F+F+F"), o).final_frame.position, {0, 0, 0});
  // $ levels the left axis.
  const auto f = interpret(word("&(30)\\(40)$"), o).final_frame;
  EXPECT_NEAR(f.left.z, 0.0, 1e-12);
}

TEST(Turtle, FrameStaysOrthonormalOver100kTurns) {
  ModuleString w;
  const char ops[] = {'+', '-', '&', '^', '\\', '/'};
  std::uint64_t h = 12345;
  for (int k = 0; k < 100000; ++k) {
    h = h * 6364136223846793005ull + 1442695040888963407ull;
    const float a = static_cast<float>((h >> 33) % 3600000) / 10000.0f;  // irrational-ish angles
    const float v[1] = {a};
    w.append(ops[(h >> 20) % 6], v);
  }
  const auto f = interpret(w, TurtleOptions{}).final_frame;
  EXPECT_NEAR(glm::length(f.heading), 1.0, 1e-12);
  EXPECT_NEAR(glm::length(f.left), 1.0, 1e-12);
  EXPECT_NEAR(glm::length(f.up), 1.0, 1e-12);
  EXPECT_NEAR(glm::dot(f.heading, f.left), 0.0, 1e-12);
  EXPECT_NEAR(glm::dot(f.heading, f.up), 0.0, 1e-12);
  EXPECT_NEAR(glm::dot(f.left, f.up), 0.0, 1e-12);
  EXPECT_NEAR(glm::dot(glm::cross(f.heading, f.left), f.up), 1.0, 1e-12);  // right-handed
}

TEST(Turtle, BracketPairReturnsExactly) {
  TurtleOptions o;
  o.tropism_strength = 0.3;
  const auto a = interpret(word("F+(17)F&(3)"), o).final_frame;
  const auto b = interpret(word("F+(17)F&(3)[+F&F\\(33)F[-F]F!(3)#(1,2,3)]"), o).final_frame;
  EXPECT_EQ(a.position, b.position);
  EXPECT_EQ(a.heading, b.heading);
  EXPECT_EQ(a.left, b.left);
  EXPECT_EQ(a.up, b.up);
}

TEST(Turtle, SkeletonBranchesAndWidths) {
  TurtleOptions o;
  o.angle = 90.0;
  const auto r = interpret(word("!(0.4)F[+F>(0.5)F]F"), o);
  ASSERT_EQ(r.skeleton.size(), 2u);
  r.skeleton.check_consistent();
  const Curve& trunk = r.skeleton.curves[0];
  const Curve& branch = r.skeleton.curves[1];
  EXPECT_EQ(trunk.parent, -1);
  EXPECT_EQ(branch.parent, 0);
  ASSERT_EQ(trunk.points.size(), 3u);  // the trunk continues after the branch
  expect_near(glm::dvec3(trunk.points[2]), {0, 0, 2});
  ASSERT_EQ(branch.points.size(), 3u);
  expect_near(glm::dvec3(branch.points[0]), {0, 0, 1});  // the branch starts on its parent
  expect_near(glm::dvec3(branch.points[2]), {-2, 0, 1});
  EXPECT_FLOAT_EQ(branch.width[1], 0.4f);
  EXPECT_FLOAT_EQ(branch.width[2], 0.2f);
  EXPECT_FLOAT_EQ(trunk.width[2], 0.4f);  // popped
  EXPECT_EQ(branch.attributes.at("depth")[0], 1.0f);
}

TEST(Turtle, LeavesCarryFrameSizeAndColor) {
  const auto r = interpret(word("FL(0.5,0,255,0)"), TurtleOptions{});
  ASSERT_EQ(r.leaves.size(), 1u);
  r.leaves.check_consistent();
  expect_near(glm::dvec3(r.leaves.position[0]), {0, 0, 1});
  EXPECT_FLOAT_EQ(r.leaves.scale[0].x, 0.5f);
  EXPECT_FLOAT_EQ(r.leaves.attributes.at("g")[0], 1.0f);
  EXPECT_FLOAT_EQ(r.leaves.attributes.at("r")[0], 0.0f);
  EXPECT_EQ(r.leaves.attributes.at("branch")[0], 0.0f);
  expect_near(glm::dvec3(r.leaves.rotation[0] * glm::vec3(1, 0, 0)), {0, 0, 1});   // x = heading
  expect_near(glm::dvec3(r.leaves.rotation[0] * glm::vec3(0, 1, 0)), {-1, 0, 0});  // y = left
}

TEST(Turtle, TropismBendsTowardsGravity) {
  TurtleOptions o;
  o.tropism_strength = 0.2;
  const auto r = interpret(word("+(90)FFFFFFFF"), o);
  const auto& p = r.skeleton.curves[0].points;
  // Heading starts horizontal (-x); each step bends it down and the steps get steeper.
  for (std::size_t i = 1; i + 1 < p.size(); ++i) EXPECT_LT(p[i + 1].z - p[i].z, p[i].z - p[i - 1].z - 1e-4);
  EXPECT_LT(r.final_frame.heading.z, -0.5);
  // Without tropism it stays horizontal.
  EXPECT_NEAR(interpret(word("+(90)FFFFFFFF"), TurtleOptions{}).final_frame.position.z, 0.0, 1e-9);
}

// --- tree mesh ------------------------------------------------------------------------------------------------

struct Topology {
  std::size_t components = 0;
  bool closed = true;  // no boundary edge
  long euler = 0;      // V - E + F
};

Topology topology(const TriMesh& m) {
  Topology t;
  for (auto h : m.halfedges())
    if (m.is_boundary(h)) t.closed = false;
  t.euler = static_cast<long>(m.n_vertices()) - static_cast<long>(m.n_edges()) + static_cast<long>(m.n_faces());
  std::vector<int> comp(m.n_vertices(), -1);
  for (auto v : m.vertices()) {
    if (comp[static_cast<std::size_t>(v.idx())] >= 0) continue;
    std::vector<TriMesh::VertexHandle> stack{v};
    comp[static_cast<std::size_t>(v.idx())] = static_cast<int>(t.components);
    while (!stack.empty()) {
      const auto u = stack.back();
      stack.pop_back();
      for (auto w : m.vv_range(u))
        if (comp[static_cast<std::size_t>(w.idx())] < 0) {
          comp[static_cast<std::size_t>(w.idx())] = static_cast<int>(t.components);
          stack.push_back(w);
        }
    }
    ++t.components;
  }
  return t;
}

double signed_volume(const TriMesh& m) {
  double v = 0.0;
  for (auto f : m.faces()) {
    auto it = m.cfv_iter(f);
    const auto a = m.point(*it), b = m.point(*++it), c = m.point(*++it);
    v +=
        glm::dot(glm::dvec3(a[0], a[1], a[2]), glm::cross(glm::dvec3(b[0], b[1], b[2]), glm::dvec3(c[0], c[1], c[2]))) /
        6.0;
  }
  return v;
}

// Winding number of the closed surface made of `faces` around p (sum of the faces' solid angles over 4 pi,
// by A. Van Oosterom, J. Strackee (1983), The solid angle of a plane triangle): 1 inside, 0 outside.
double winding_number(const TriMesh& m, const std::vector<TriMesh::FaceHandle>& faces, const glm::dvec3& p) {
  double sum = 0.0;
  for (auto f : faces) {
    auto it = m.cfv_iter(f);
    const auto pa = m.point(*it), pb = m.point(*++it), pc = m.point(*++it);
    const glm::dvec3 a = glm::dvec3(pa[0], pa[1], pa[2]) - p, b = glm::dvec3(pb[0], pb[1], pb[2]) - p,
                     c = glm::dvec3(pc[0], pc[1], pc[2]) - p;
    const double la = glm::length(a), lb = glm::length(b), lc = glm::length(c);
    sum += 2.0 * std::atan2(glm::dot(a, glm::cross(b, c)),
                            la * lb * lc + glm::dot(a, b) * lc + glm::dot(a, c) * lb + glm::dot(b, c) * la);
  }
  return sum / (4.0 * std::numbers::pi);
}

// Every face normal is unit length, agrees with the face's vertex winding (the right-hand normal of a, b, c)
// and with the vertex normals set by the mesher, and points out of its closed component: a point just in
// front of the face is outside the component (winding number 0), a point just behind it inside (1).
void expect_outward_unit_normals(const TriMesh& m) {
  std::vector<int> comp(m.n_vertices(), -1);
  int components = 0;
  for (auto v : m.vertices()) {
    if (comp[static_cast<std::size_t>(v.idx())] >= 0) continue;
    std::vector<TriMesh::VertexHandle> stack{v};
    comp[static_cast<std::size_t>(v.idx())] = components;
    while (!stack.empty()) {
      const auto u = stack.back();
      stack.pop_back();
      for (auto w : m.vv_range(u))
        if (comp[static_cast<std::size_t>(w.idx())] < 0) {
          comp[static_cast<std::size_t>(w.idx())] = components;
          stack.push_back(w);
        }
    }
    ++components;
  }
  std::vector<std::vector<TriMesh::FaceHandle>> faces_of(static_cast<std::size_t>(components));
  for (auto f : m.faces()) {
    const int first = m.cfv_iter(f)->idx();
    faces_of[static_cast<std::size_t>(comp[static_cast<std::size_t>(first)])].push_back(f);
  }
  std::size_t checked = 0;
  for (auto f : m.faces()) {
    auto it = m.cfv_iter(f);
    const auto va = *it, vb = *++it, vc = *++it;
    const auto to_d = [&](TriMesh::VertexHandle v) {
      const auto q = m.point(v);
      return glm::dvec3(q[0], q[1], q[2]);
    };
    const glm::dvec3 a = to_d(va), b = to_d(vb), c = to_d(vc);
    const glm::dvec3 cr = glm::cross(b - a, c - a);
    const double shortest = std::min({glm::length(b - a), glm::length(c - b), glm::length(a - c)});
    if (glm::length(cr) < 1e-6 * shortest * shortest || shortest < 1e-5) continue;  // a sliver: no direction
    ++checked;
    const auto fn = m.normal(f);
    const glm::dvec3 n(fn[0], fn[1], fn[2]);
    ASSERT_NEAR(glm::length(n), 1.0, 1e-5) << "face " << f.idx();
    ASSERT_GT(glm::dot(n, glm::normalize(cr)), 0.999) << "face " << f.idx() << " disagrees with its winding";
    glm::dvec3 vertex_normals(0.0);
    for (auto v : {va, vb, vc}) {
      const auto vn = m.normal(v);
      ASSERT_NEAR(glm::length(glm::dvec3(vn[0], vn[1], vn[2])), 1.0, 1e-5) << "vertex " << v.idx();
      vertex_normals += glm::dvec3(vn[0], vn[1], vn[2]);
    }
    ASSERT_GT(glm::dot(n, vertex_normals), 0.0) << "face " << f.idx() << " faces against its vertex normals";
    const glm::dvec3 centre = (a + b + c) / 3.0;
    const double eps = 1e-3 * shortest;
    const auto& own = faces_of[static_cast<std::size_t>(comp[static_cast<std::size_t>(va.idx())])];
    ASSERT_NEAR(winding_number(m, own, centre + eps * n), 0.0, 0.25) << "face " << f.idx() << " points inward";
    ASSERT_NEAR(winding_number(m, own, centre - eps * n), 1.0, 0.25) << "face " << f.idx() << " points inward";
  }
  EXPECT_GT(checked, m.n_faces() * 9 / 10) << "most faces are checked";
}

TEST(TreeMesh, StraightBranchIsAClosedOutwardPrism) {
  TurtleOptions o;
  const auto r = interpret(word("!(0.2)FF"), o);
  TreeMeshOptions mo;
  mo.sides = 8;
  TreeMeshStats st;
  const Mesh mesh = tree_mesh(r.skeleton, nullptr, mo, &st);
  const auto t = topology(mesh.mesh);
  EXPECT_TRUE(t.closed);
  EXPECT_EQ(t.components, 1u);
  EXPECT_EQ(t.euler, 2);
  // Volume of an 8-gon prism of circumradius 0.1 and length 2: (k/2) r^2 sin(2 pi / k) L.
  EXPECT_NEAR(signed_volume(mesh.mesh), 4.0 * 0.01 * std::sin(std::numbers::pi / 4.0) * 2.0, 1e-5);
  EXPECT_EQ(mesh.face_count(), 2u * 8u * 3u);
  expect_outward_unit_normals(mesh.mesh);
  // It stands on the ground: nothing below z = 0.
  float zmin = 1e9f;
  for (auto v : mesh.mesh.vertices()) zmin = std::min(zmin, mesh.mesh.point(v)[2]);
  EXPECT_NEAR(zmin, 0.0f, 1e-6f);
}

Curves bush_skeleton(int iterations, std::uint64_t seed = 3) {
  const LSystem l("!(0.3)F", "F -> F[+F!(0.5)F]F[-F]F : 1\nF -> F[&F]F[^F]F : 1\nF -> F[\\\\+F][/-F]F : 1");
  DeriveOptions d;
  d.iterations = iterations;
  d.seed = seed;
  TurtleOptions o;
  o.tropism_strength = 0.05;
  return interpret(l.derive(d), o).skeleton;
}

TEST(TreeMesh, EveryBranchIsAClosedManifoldWithOutwardFaces) {
  const Curves sk = bush_skeleton(3);
  ASSERT_GT(sk.size(), 20u);
  TreeMeshOptions mo;
  mo.sides = 6;
  const Mesh mesh = tree_mesh(sk, nullptr, mo);
  const auto t = topology(mesh.mesh);
  EXPECT_TRUE(t.closed);
  EXPECT_EQ(t.components, sk.size());                    // one closed tube per branch
  EXPECT_EQ(t.euler, 2 * static_cast<long>(sk.size()));  // each a topological sphere
  // Consistent outward winding: every branch encloses a positive volume.
  EXPECT_GT(signed_volume(mesh.mesh), 0.0);
  expect_outward_unit_normals(mesh.mesh);
}

TEST(TreeMesh, TriangleBudgetRespected) {
  const Curves sk = bush_skeleton(4);
  TreeMeshOptions mo;
  mo.sides = 12;
  const std::size_t full = tree_mesh(sk, nullptr, mo).face_count();
  for (std::size_t budget : {full, full / 2, full / 4, full / 5, full / 20, std::size_t(500), std::size_t(16)}) {
    mo.max_triangles = budget;
    TreeMeshStats st;
    const Mesh m = tree_mesh(sk, nullptr, mo, &st);
    EXPECT_LE(m.face_count(), budget) << budget;
    const auto t = topology(m.mesh);
    EXPECT_TRUE(t.closed) << budget;
    if (budget == full) {
      EXPECT_EQ(st.sides, 12);
    }
    if (budget >= full / 4) {
      EXPECT_EQ(st.dropped_branches, 0u) << budget;  // 3 sides suffice
    } else {
      EXPECT_GT(st.dropped_branches, 0u) << budget;
    }
  }
}

TEST(TreeMesh, LeafQuadsFaceTheirUpAxis) {
  const auto r = interpret(word("F[&L(0.5)][^L(0.4)]L"), TurtleOptions{});
  TreeMeshOptions mo;
  TreeMeshStats st;
  const Mesh m = tree_mesh(r.skeleton, &r.leaves, mo, &st);
  EXPECT_EQ(st.leaf_triangles, 6u);
  // The last six faces are the leaves; their normals agree with each leaf's up axis.
  TriMesh mm = m.mesh;
  mm.update_face_normals();
  std::size_t k = 0;
  for (auto f : mm.faces()) {
    if (k++ < st.branch_triangles) continue;
    const std::size_t leaf = (k - 1 - st.branch_triangles) / 2;
    const glm::dvec3 up = glm::dquat(r.leaves.rotation[leaf]) * glm::dvec3(0, 0, 1);
    const auto n = mm.normal(f);
    EXPECT_GT(up.x * n[0] + up.y * n[1] + up.z * n[2], 0.99);
  }
}

TEST(TreeMesh, RockLeavesAreClosed) {
  const auto r = interpret(word("F[&L(0.5)][^L(0.4)]L"), TurtleOptions{});
  TreeMeshOptions mo;
  mo.leaf_shape = LeafShape::Rock;
  const Mesh m = tree_mesh(r.skeleton, &r.leaves, mo);
  const auto t = topology(m.mesh);
  EXPECT_TRUE(t.closed);
  EXPECT_EQ(t.components, 4u);
  EXPECT_EQ(t.euler, 8);
}

TEST(TreeMesh, TextureCoordinatesRunAroundAndAlongAndSurviveSerialization) {
  const auto r = interpret(word("!(0.2)F(2)F(1)"), TurtleOptions{});
  TreeMeshOptions mo;
  mo.sides = 4;
  const Mesh m = tree_mesh(r.skeleton, nullptr, mo);
  ASSERT_TRUE(m.mesh.has_vertex_texcoords2D());
  // Ring vertices: u = j / k around, v = arc length (0, 2, 3 m).
  const auto t = m.mesh.texcoord2D(TriMesh::VertexHandle(4 * 2 + 3));
  EXPECT_FLOAT_EQ(t[0], 0.75f);
  EXPECT_FLOAT_EQ(t[1], 3.0f);
  const PortValue back = deserialize_value(serialize_value(PortValue(MeshPtr(std::make_shared<Mesh>(m)))));
  const auto& bm = std::get<MeshPtr>(back)->mesh;
  ASSERT_TRUE(bm.has_vertex_texcoords2D());
  EXPECT_EQ(bm.texcoord2D(TriMesh::VertexHandle(11)), t);
}

TEST(TreeMesh, GltfRoundTrip) {
  const auto r = interpret(word("!(0.2)F[+F]F"), TurtleOptions{});
  const Mesh m = tree_mesh(r.skeleton, &r.leaves, TreeMeshOptions{});
  const auto dir = test::scratch_dir("plants-gltf");
  for (const char* name : {"tree.glb", "tree.gltf"}) {
    const auto path = dir / name;
    write_mesh_file(m, path, *mesh_format_from_path(path));
    tinygltf::Model model;
    tinygltf::TinyGLTF loader;
    std::string err, warn;
    const bool ok = std::string(name).ends_with(".glb") ? loader.LoadBinaryFromFile(&model, &err, &warn, path.string())
                                                        : loader.LoadASCIIFromFile(&model, &err, &warn, path.string());
    ASSERT_TRUE(ok) << err;
    ASSERT_EQ(model.meshes.size(), 1u);
    const auto& prim = model.meshes[0].primitives.at(0);
    for (const char* attr : {"POSITION", "NORMAL", "COLOR_0", "TEXCOORD_0"}) {
      ASSERT_TRUE(prim.attributes.count(attr)) << attr;
      EXPECT_EQ(model.accessors[static_cast<std::size_t>(prim.attributes.at(attr))].count, m.vertex_count()) << attr;
    }
    EXPECT_EQ(model.accessors[static_cast<std::size_t>(prim.indices)].count, 3 * m.face_count());
    // y-up: the tree's height (z in Orogen) is the file's y.
    const auto& pos = model.accessors[static_cast<std::size_t>(prim.attributes.at("POSITION"))];
    EXPECT_NEAR(pos.maxValues[1], 2.0, 1e-5);
    EXPECT_NEAR(pos.minValues[1], 0.0, 1e-5);
  }
}

// --- PlantSprite ---------------------------------------------------------------------------------------------

std::size_t count_symbol(const ModuleString& w, char c) {
  return static_cast<std::size_t>(std::count(w.symbols.begin(), w.symbols.end(), c));
}

void mesh_bounds(const Mesh& m, OpenMesh::Vec3f& lo, OpenMesh::Vec3f& hi) {
  lo = OpenMesh::Vec3f(1e30f);
  hi = OpenMesh::Vec3f(-1e30f);
  for (auto v : m.mesh.vertices()) {
    lo.minimize(m.mesh.point(v));
    hi.maximize(m.mesh.point(v));
  }
}

TEST(PlantSprite, OneQuadPerSegmentAndLeafPerPlane) {
  // 3D Game Worlds' rule 4.19 (322 modules after 3 steps), with a leaf at every X.
  const LSystem rule("X", "X -> [FF[+XF-F+FX]--F+F-FX]\nF -> FF");
  DeriveOptions d;
  d.iterations = 3;
  const ModuleString w = rule.derive(d);
  ASSERT_EQ(w.size(), 322u);
  const std::size_t f = count_symbol(w, 'F'), x = count_symbol(w, 'X');
  ASSERT_GT(f, 100u);
  ASSERT_GT(x, 10u);
  PlantSpriteOptions o;
  o.angle = 30.0;
  for (const bool crossed : {false, true}) {
    o.crossed = crossed;
    const std::size_t planes = crossed ? 2 : 1;
    o.leaf_symbol = '\0';
    PlantSpriteStats st;
    const Mesh bare = plant_sprite(w, o, &st);
    EXPECT_EQ(st.segments, f);
    EXPECT_EQ(st.leaves, 0u);
    EXPECT_EQ(bare.vertex_count(), 4 * f * planes);
    EXPECT_EQ(bare.face_count(), 2 * f * planes);
    o.leaf_symbol = 'X';
    const Mesh leafy = plant_sprite(w, o, &st);
    EXPECT_EQ(st.leaves, x);
    EXPECT_EQ(leafy.vertex_count(), 4 * (f + x) * planes);
    EXPECT_EQ(leafy.face_count(), 2 * (f + x) * planes);
    // Every face is a proper triangle facing its plane's normal.
    for (auto fh : leafy.mesh.faces()) {
      std::vector<OpenMesh::Vec3f> p;
      for (auto v : leafy.mesh.fv_range(fh)) p.push_back(leafy.mesh.point(v));
      ASSERT_EQ(p.size(), 3u);
      const auto n = (p[1] - p[0]) % (p[2] - p[0]);
      const auto expected = leafy.mesh.normal(fh);
      if (n.norm() > 1e-9f) {
        EXPECT_GT(n.normalized() | expected, 0.999f);
      }
    }
  }
  // The budget: over it is an error, not a truncated plant.
  o.max_triangles = 2 * f;  // one plane's worth of segments, but two planes and leaves are asked
  EXPECT_THROW(plant_sprite(w, o), std::invalid_argument);
}

TEST(PlantSprite, StandsOnZeroAndStraightStemHeightIsAnalytic) {
  PlantSpriteOptions o;
  o.step = 0.35;
  o.width = 0.2;
  o.leaf_symbol = '\0';
  PlantSpriteStats st;
  // Five straight segments: 5 * 0.35 m tall, base at z = 0, width across x (and y in the crossed plane).
  const Mesh stem = plant_sprite(word("FFFFF"), o, &st);
  OpenMesh::Vec3f lo, hi;
  mesh_bounds(stem, lo, hi);
  EXPECT_FLOAT_EQ(lo[2], 0.0f);
  EXPECT_NEAR(hi[2], 5 * 0.35, 1e-6);
  EXPECT_NEAR(st.height, 5 * 0.35, 1e-12);
  EXPECT_FLOAT_EQ(hi[0] - lo[0], 0.2f);
  EXPECT_FLOAT_EQ(hi[1] - lo[1], 0.2f);
  // A parameter overrides the step; a turn of 60 degrees halves the vertical progress (cos 60); f moves.
  mesh_bounds(plant_sprite(word("F(2)+(60)F(2)f(1)"), o, &st), lo, hi);
  EXPECT_NEAR(hi[2] - lo[2], 2.0 + 2.0 * 0.5 + 0.5 * 0.2 * std::sin(std::numbers::pi / 3), 1e-5);
  // A plant drooping below its root is lifted so that its lowest point is at z = 0.
  o.angle = 150.0;
  mesh_bounds(plant_sprite(word("F[+FF][-FF]"), o, &st), lo, hi);
  EXPECT_NEAR(lo[2], 0.0f, 1e-6);
  EXPECT_GT(hi[2], 0.3f);
  // Branch levels narrow by taper; ! sets the width.
  o.angle = 90.0;
  o.taper = 0.5;
  o.crossed = false;
  mesh_bounds(plant_sprite(word("[[+F]]"), o, &st), lo, hi);
  EXPECT_NEAR(hi[2] - lo[2], 0.2 * 0.25, 1e-6) << "a horizontal segment two levels deep is width / 4 tall";
  mesh_bounds(plant_sprite(word("!(0.6)+F"), o, &st), lo, hi);
  EXPECT_NEAR(hi[2] - lo[2], 0.6, 1e-6);
  // A leaf of size s on top of a stem: s taller, s / 2 wide.
  o.leaf_symbol = 'L';
  mesh_bounds(plant_sprite(word("FL(0.4)"), o, &st), lo, hi);
  EXPECT_NEAR(hi[2], 0.35 + 0.4, 1e-6);
  EXPECT_EQ(st.leaves, 1u);
}

TEST(PlantSprite, DeterministicAndNodeFeedsInstance) {
  const Domain d = Domain::from_extent({0, 0}, {10, 10}, {4, 4});
  const std::map<std::string, ParamValue> p{
      {"axiom", std::string("X")},
      {"rules", std::string("X -> F[+XL][-XL]FX : 1; X -> F[-XL]FX : 1\nF -> FF")},
      {"iterations", std::int64_t(4)},
      {"seed", std::uint64_t(3)}};
  const auto w = run_node("LSystem", d, p).get<ModuleString>();
  const auto a = run_node("PlantSprite", d, {}, {{"in", PortValue(w)}}).get<Mesh>();
  const auto b = run_node("PlantSprite", d, {}, {{"in", PortValue(w)}}).get<Mesh>();
  ASSERT_GT(a->face_count(), 0u);
  ASSERT_EQ(a->vertex_count(), b->vertex_count());
  for (auto v : a->mesh.vertices()) ASSERT_EQ(a->mesh.point(v), b->mesh.point(TriMesh::VertexHandle(v.idx())));
  EXPECT_EQ(serialize_value(PortValue(MeshPtr(a))), serialize_value(PortValue(MeshPtr(b))));
  // A leaf symbol longer than one character is a clear error.
  EXPECT_THROW(run_node("PlantSprite", d, {{"leaf_symbol", std::string("LL")}}, {{"in", PortValue(w)}}), NodeError);
  // Instanced like any class mesh: each instance stands on its point.
  auto pts = std::make_shared<Points>();
  pts->add({5, 5, 12}, 0);
  pts->add({1, 2, 3}, 0);
  const auto scene =
      run_node("Instance", d, {}, {{"in", PortValue(PointsPtr(pts))}, {"mesh_0", PortValue(MeshPtr(a))}}).get<Scene>();
  ASSERT_EQ(scene->size(), 2u);
  EXPECT_EQ(scene->classes.at(0).mesh, a);
}

TEST(PlantNodes, EveryParameterAndInputChangesTheKey) {
  const Domain d = Domain::from_extent({0, 0}, {10, 10}, {4, 4});
  for (const char* type : {"LSystem", "Turtle3D", "TreeMesh", "PlantSprite"}) {
    expect_every_param_changes_key(type, d);
    expect_every_input_changes_key(type, d);
  }
}

TEST(PlantNodes, ChainRunsAndSeedChangesTheWord) {
  const Domain d = Domain::from_extent({0, 0}, {10, 10}, {4, 4});
  const std::map<std::string, ParamValue> p{{"axiom", std::string("F")},
                                            {"rules", std::string("F -> F[+F]F : 1; F -> F[-F]F : 1")},
                                            {"iterations", std::int64_t(3)}};
  auto w1 = run_node("LSystem", d, p).get<ModuleString>();
  auto p2 = p;
  p2["seed"] = std::uint64_t(5);
  auto w2 = run_node("LSystem", d, p2).get<ModuleString>();
  EXPECT_NE(w1->text(), w2->text());
  const auto t = run_node("Turtle3D", d, {}, {{"in", PortValue(w1)}});
  const auto mesh = run_node("TreeMesh", d, {}, {{"in", t.outputs[0]}, {"leaves", t.outputs[1]}}).get<Mesh>();
  EXPECT_GT(mesh->face_count(), 0u);
  // A bad grammar is a clear node error.
  auto bad = p;
  bad["rules"] = std::string("F -> F[");
  try {
    run_node("LSystem", d, bad);
    FAIL();
  } catch (const NodeError& e) {
    EXPECT_NE(std::string(e.what()).find("column"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace orogen::plants
