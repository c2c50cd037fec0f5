// Plants: L-system derivation (ABOP reference words, context across brackets, parametric and conditional
// rules, stochastic determinism and weight distribution, grammar errors with positions), the 3D turtle
// (orthonormal frame, known end points, bracket return, tropism) and tree meshes (closed per branch,
// consistent winding, triangle budget).
#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <string>

#include <gtest/gtest.h>

#include "evaluator/value_serialization.h"
#include "graph/module_string.h"
#include "nodes/plants/lsystem.h"

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
  EXPECT_EQ(derive_text("A[C]B", "A < B -> X", 1), "A[C]X");   // sibling branch skipped
  EXPECT_EQ(derive_text("A[B]", "A < B -> X", 1), "A[X]");     // branch start: parent is A
  EXPECT_EQ(derive_text("C[A]B", "A < B -> X", 1), "C[A]B");   // A is in a sibling branch, not an ancestor
  EXPECT_EQ(derive_text("A[C][D]B", "A < B -> X", 1), "A[C][D]X");
  EXPECT_EQ(derive_text("AF+B", "A < B -> X", 1), "AF+B");     // F and + are modules unless ignored
  EXPECT_EQ(derive_text("AF+B", "A < B -> X", 1, 0, "F+"), "AF+X");
}

TEST(LSystem, RightContextSkipsBranchesAndMatchesBracketPatterns) {
  EXPECT_EQ(derive_text("A[C]B", "A > B -> X", 1), "X[C]B");     // branch between skipped
  EXPECT_EQ(derive_text("[A]B", "A > B -> X", 1), "[A]B");        // end of branch: no successor
  EXPECT_EQ(derive_text("A[C]B", "A > [C]B -> X", 1), "X[C]B");   // bracketed pattern
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
  const std::string a = derive_text("F", rules, 4, 7), b = derive_text("F", rules, 4, 7), c = derive_text("F", rules, 4, 8);
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
  // Random draws in parameters too.
  const std::string r = "A -> B(uniform(0, 1)) A";
  EXPECT_EQ(derive_text("A", r, 5, 1), derive_text("A", r, 5, 1));
  EXPECT_NE(derive_text("A", r, 5, 1), derive_text("A", r, 5, 2));
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

TEST(LSystem, CommentsAndBlankLines) {
  EXPECT_EQ(derive_text("A", "// algae\n\n  A -> AB ; B -> A\n", 2), "ABA");
}

TEST(LSystem, ModuleStringRoundTripsThroughSerialization) {
  const LSystem l("A(1)", "A(x) -> A(x+0.5)[+B(x, 2)]");
  DeriveOptions o;
  const ModuleString w = l.derive(o);
  const PortValue back = deserialize_value(serialize_value(PortValue(ModuleStringPtr(std::make_shared<ModuleString>(w)))));
  ASSERT_EQ(port_type_of(back), PortType::ModuleString);
  EXPECT_EQ(std::get<ModuleStringPtr>(back)->text(), w.text());
  EXPECT_EQ(w.text(), "A(2.5)[+B(2,2)][+B(1.5,2)][+B(1,2)]");
}

}  // namespace
}  // namespace orogen::plants
