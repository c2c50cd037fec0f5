#pragma once
// Parametric, stochastic, context-sensitive bracketed L-systems in the notation of Prusinkiewicz &
// Lindenmayer (1990), The Algorithmic Beauty of Plants (ABOP), chapters 1-2. See docs/lsystems.md.
//
// Rules, one per line (or separated by ';'):
//
//   [left context <] predecessor [> right context] [: condition] -> successor [: weight]
//
//   A -> AB                               context-free
//   b < a -> b                            left context (skips bracketed branches, see below)
//   A(x) > B(y) : x < y -> A(x+1)[+B(y/2)] parametric with a condition
//   F -> F[+F]F : 1                       stochastic: alternatives weighted 1 : 2
//   F -> F[-F]F : 2
//   let d = 25                            a named constant usable in every expression
//
// Modules are single printable ASCII characters (not ( ) , : ; or space) with optional parameters in
// parentheses. Expressions: numbers, + - * / ^ (power), unary -, comparisons, && || !, parentheses,
// functions sin cos tan asin acos atan atan2 sqrt abs min max floor ceil exp log pow clamp (degrees for the
// trigonometric functions), constants pi and e, and random draws uniform(a, b) (alias U) and gauss(m, s)
// (alias N). Every draw is a counter-based hash of (seed, iteration, module index, draw number): the same
// seed gives the same word for any build or thread count.
//
// Rule selection for a module: the rules whose predecessor (symbol and parameter count), contexts and
// condition match; if any of them has a context, only those with a context remain (context-sensitive rules
// take precedence); then one is chosen by the roulette of their weights (ABOP §1.7's stochastic L-systems,
// weights normalized to probabilities); none: the module is copied. Context matching follows ABOP's bracketed
// rules: the left context is searched towards the root (a ']' skips the whole branch before it, a '[' is
// stepped over to the parent); the right context skips the branches between modules, a '[' in the pattern
// enters a branch of the word, a ']' skips the rest of the branch. Symbols in the ignore list are skipped by both.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>

#include "graph/module_string.h"

namespace orogen::plants {

// A grammar error with its position: `where` names the text ("rules" or "axiom"), line and column count from
// 1 (bytes in the original text).
struct LSystemError : std::invalid_argument {
  LSystemError(const std::string& where, int line, int column, const std::string& what);
  std::string where;
  int line = 0, column = 0;
};

struct DeriveOptions {
  int iterations = 3;
  std::uint64_t seed = 0;
  std::size_t max_modules = 1000000;  // a word longer than this fails (LSystemError) instead of growing on
  std::function<void(double)> progress;
  std::function<bool()> should_stop;  // checked between iterations and every few thousand modules
};

class LSystem {
 public:
  // Parses the grammar; throws LSystemError. `ignore` lists symbols that context matching skips.
  LSystem(const std::string& axiom, const std::string& rules, const std::string& ignore = "");
  ~LSystem();
  LSystem(LSystem&&) noexcept;
  LSystem& operator=(LSystem&&) noexcept;

  // The axiom after `iterations` parallel rewriting steps. Throws LSystemError when the word would exceed
  // max_modules; returns early (partial word) when should_stop says so.
  ModuleString derive(const DeriveOptions& options) const;
  // The same word, written into `word`; `spare` (a distinct object) holds the other word of each step. A caller
  // that derives again and again keeps both: once they have grown, a derivation allocates nothing and touches no
  // new pages. On an error both hold unspecified words.
  void derive(const DeriveOptions& options, ModuleString& word, ModuleString& spare) const;
  // One rewriting step of `word` as step number `iteration` (0-based; part of the random draws' key).
  ModuleString step(const ModuleString& word, int iteration, std::uint64_t seed,
                    std::size_t max_modules = static_cast<std::size_t>(-1)) const;
  // The same step written into `out` (a distinct object), reusing its buffers.
  void step(const ModuleString& word, ModuleString& out, int iteration, std::uint64_t seed,
            std::size_t max_modules = static_cast<std::size_t>(-1)) const;
  // The evaluated axiom (random draws in it use iteration -1).
  ModuleString axiom(std::uint64_t seed) const;
  std::size_t rule_count() const;
  // The most parameters a module of the axiom or of a successor carries: a bound for every derived module.
  std::size_t max_module_parameters() const;
  // An upper bound on the word's length after `iterations` steps, at most `cap`: symbol counts grown step by
  // step, each symbol replaced by the most of every symbol any of its rules' successors holds (or kept, when no
  // rule applies: conditions, contexts and stochastic choices may all fail). Exact for context-free
  // deterministic grammars (algae: Fibonacci numbers); O(iterations x symbols^2).
  std::uint64_t max_word_length(int iterations, std::uint64_t cap) const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

// The bytes a derivation holds at its peak when its word may grow to `max_modules` modules of at most
// `parameters` each: the word being read and the word being written (a symbol, an offset and the parameters per
// module, twice: a step sizes its output by what each module can become, which conditions and stochastic choices
// may leave unused) and the bracket-matching index of context rules.
std::uint64_t derive_peak_bytes(std::size_t max_modules, std::size_t parameters);

// Convenience: parse and derive; the text of the result.
std::string derive_text(const std::string& axiom, const std::string& rules, int iterations, std::uint64_t seed = 0,
                        const std::string& ignore = "");

}  // namespace orogen::plants
