// Plants and rocks: L-system derivation throughput, turtle and tree meshing of SeamScape's green tree
// (S. Ekman et al. 2016, SeamScape, Appendix A; the preset of graphs/plants.json), and convex hulls of 20 and
// 100 points on an ellipsoid (CGAL's convex_hull_3, the quickhull of Barber, Dobkin & Huhdanpaa 1996) and
// whole hull rocks.
//
//   Derive/rule_4_20/<iterations>  context-free bracketed grammar (3D Game Worlds rule 4.20, F -> FF)
//   DeriveFresh/rule_4_20/<iter.>  the same with new buffers for every derivation (the node's case)
//   StringRewrite/rule_4_20/<it.>  the reference: the same rule as a plain std::string rewrite
//   Derive/green_tree/<iterations> parametric, stochastic, conditional, with random draws
//   Turtle/green_tree/5, TreeMesh/green_tree/5   the 5-iteration tree (skeleton, then mesh with leaves)
//   Hull/cgal/<n>, Hull/small/<n>  hull alone (CGAL, the small-set incremental hull); HullRock/<n>: sampling
//                                  + hull + mesh
//
// Counter modules_per_s / hulls: read the CPU column; run on one core, e.g.
//   taskset -c 0 build/release/bench/orogen_bench_plants
// The machine may be shared.
#include <benchmark/benchmark.h>

#include <string>

#include "graph/mesh.h"
#include "nodes/plants/lsystem.h"
#include "nodes/plants/tree_mesh.h"
#include "nodes/plants/turtle.h"
#include "nodes/rocks/hull_rock.h"

namespace {

using namespace orogen;

const char* kGreenTree =
    "T(r,g,b,a) -> #(r,g,b)>F(0.5,1)[T(r,g,b,0.99*a)][+(60+U(-30,30))T(r,g,b,0.99*a)][-(60+U(-30,30))T(r,g,b,0.99*a)]"
    "[&(60+U(-30,30))T(r,g,b,0.99*a)][^(60+U(-30,30))T(r,g,b,0.99*a)] : 75\n"
    "F(d,n) -> F(1.7*d,n)>\n"
    "T(r,g,b,a) : a < 98 -> F(0.8,1)L(1.2,40,140+U(-30,30),40) : 25";

// The word and its spare are reused from one derivation to the next, as a caller deriving repeatedly keeps them:
// the benchmark measures the rewriting, not the kernel's first touch of fresh pages. DeriveFresh allocates both
// anew every time, as the LSystem node does for its single derivation.
void derive(benchmark::State& state, const char* axiom, const char* rules, bool reuse = true) {
  const plants::LSystem l(axiom, rules);
  plants::DeriveOptions o;
  o.iterations = static_cast<int>(state.range(0));
  o.seed = 7;
  o.max_modules = 100000000;
  ModuleString word, spare;
  for (auto _ : state) {
    if (reuse)
      l.derive(o, word, spare);
    else
      word = l.derive(o);
    benchmark::DoNotOptimize(word.symbols.data());
  }
  state.counters["modules"] = static_cast<double>(word.size());
  state.counters["modules_per_s"] =
      benchmark::Counter(static_cast<double>(word.size()), benchmark::Counter::kIsIterationInvariantRate);
}

void BM_Derive_rule_4_20(benchmark::State& s) { derive(s, "X", "X -> F-[[X]+X]+F[+FX]-X\nF -> FF"); }
BENCHMARK(BM_Derive_rule_4_20)->Name("Derive/rule_4_20")->Arg(9)->Unit(benchmark::kMillisecond);
void BM_DeriveFresh_rule_4_20(benchmark::State& s) { derive(s, "X", "X -> F-[[X]+X]+F[+FX]-X\nF -> FF", false); }
BENCHMARK(BM_DeriveFresh_rule_4_20)->Name("DeriveFresh/rule_4_20")->Arg(9)->Unit(benchmark::kMillisecond);

// The reference: rule 4.20 rewritten as a plain std::string, one byte per module, the two buffers reused.
void BM_StringRewrite_rule_4_20(benchmark::State& state) {
  const int iterations = static_cast<int>(state.range(0));
  const std::string x = "F-[[X]+X]+F[+FX]-X";
  std::string word, next;
  for (auto _ : state) {
    word.clear();  // the axiom X (assign("X") trips a false -Wrestrict of GCC 12)
    word.push_back('X');
    for (int it = 0; it < iterations; ++it) {
      next.clear();
      for (const char c : word) {
        if (c == 'X')
          next.append(x);
        else if (c == 'F')
          next.append("FF", 2);
        else
          next.push_back(c);
      }
      word.swap(next);
    }
    benchmark::DoNotOptimize(word.data());
  }
  state.counters["modules"] = static_cast<double>(word.size());
  state.counters["modules_per_s"] =
      benchmark::Counter(static_cast<double>(word.size()), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_StringRewrite_rule_4_20)->Name("StringRewrite/rule_4_20")->Arg(9)->Unit(benchmark::kMillisecond);

void BM_Derive_green(benchmark::State& s) { derive(s, "T(140,90,40,100)", kGreenTree); }
BENCHMARK(BM_Derive_green)->Name("Derive/green_tree")->Arg(5)->Arg(8)->Unit(benchmark::kMillisecond);

ModuleString green_tree_word(int iterations) {
  plants::DeriveOptions o;
  o.iterations = iterations;
  o.seed = 7;
  return plants::LSystem("T(140,90,40,100)", kGreenTree).derive(o);
}

plants::TurtleOptions green_turtle() {
  plants::TurtleOptions t;
  t.width = 0.9;
  t.width_factor = 0.8;
  t.tropism_strength = 0.05;
  return t;
}

void BM_Turtle(benchmark::State& state) {
  const ModuleString w = green_tree_word(5);
  for (auto _ : state) benchmark::DoNotOptimize(plants::interpret(w, green_turtle()));
  state.counters["modules"] = static_cast<double>(w.size());
}
BENCHMARK(BM_Turtle)->Name("Turtle/green_tree/5")->Unit(benchmark::kMillisecond);

void BM_TreeMesh(benchmark::State& state) {
  const auto r = plants::interpret(green_tree_word(5), green_turtle());
  plants::TreeMeshOptions o;
  std::size_t faces = 0;
  for (auto _ : state) {
    const Mesh m = plants::tree_mesh(r.skeleton, &r.leaves, o);
    faces = m.face_count();
  }
  state.counters["triangles"] = static_cast<double>(faces);
  state.counters["branches"] = static_cast<double>(r.skeleton.size());
}
BENCHMARK(BM_TreeMesh)->Name("TreeMesh/green_tree/5")->Unit(benchmark::kMillisecond);

// 64 seeded rock point sets of state.range(0) points, hulled in turn by `hull`.
template <class Hull>
void hull_benchmark(benchmark::State& state, Hull&& hull) {
  std::vector<std::vector<glm::dvec3>> sets;
  for (std::uint64_t k = 0; k < 64; ++k) {
    rocks::HullRockOptions o;
    o.points = static_cast<int>(state.range(0));
    o.seed = k;
    sets.push_back(rocks::rock_points(o));
  }
  std::size_t k = 0;
  for (auto _ : state) benchmark::DoNotOptimize(hull(sets[k++ % sets.size()]));
  state.counters["hulls"] = benchmark::Counter(1.0, benchmark::Counter::kIsIterationInvariantRate);
}

void BM_Hull(benchmark::State& state) {
  hull_benchmark(state, [](const auto& points) { return rocks::convex_hull_cgal(points); });
}
BENCHMARK(BM_Hull)->Name("Hull/cgal")->Arg(20)->Arg(100)->Unit(benchmark::kMicrosecond);

void BM_SmallHull(benchmark::State& state) {
  hull_benchmark(state, [](const auto& points) { return rocks::convex_hull_small(points); });
}
BENCHMARK(BM_SmallHull)->Name("Hull/small")->Arg(20)->Arg(100)->Unit(benchmark::kMicrosecond);

void BM_HullRock(benchmark::State& state) {
  rocks::HullRockOptions o;
  o.points = static_cast<int>(state.range(0));
  for (auto _ : state) {
    Mesh m;
    ++o.seed;
    rocks::append_hull_rock(m.mesh, o, glm::dvec3(0.0), glm::dquat(1, 0, 0, 0), TriMesh::Color(0.5f, 0.5f, 0.5f, 1.0f));
    benchmark::DoNotOptimize(m.mesh.n_faces());
  }
}
BENCHMARK(BM_HullRock)->Name("HullRock")->Arg(20)->Arg(100)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
