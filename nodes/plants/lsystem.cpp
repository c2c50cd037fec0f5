// The L-system rewriter (lsystem.h): parallel rewriting of a word, rule selection by predecessor, contexts,
// condition and weighted roulette. Parsing is in lsystem_parser.cpp, expressions in lsystem_eval.h.
#include "nodes/plants/lsystem.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <span>
#include <vector>

#include "nodes/common/hash.h"
#include "nodes/plants/lsystem_grammar.h"

namespace orogen::plants {

using lsys::draw_key;
using lsys::Draws;
using lsys::eval;
using lsys::kMaxParams;
using lsys::kMaxSlots;
using lsys::Pattern;
using lsys::Rule;
using lsys::Template;

LSystemError::LSystemError(const std::string& where_, int line_, int column_, const std::string& what)
    : std::invalid_argument(where_ + (line_ > 0 ? " line " + std::to_string(line_) : std::string()) +
                            (column_ > 0 ? ", column " + std::to_string(column_) : std::string()) + ": " + what),
      where(where_),
      line(line_),
      column(column_) {}

struct LSystem::Impl {
  std::vector<lsys::Template> axiom;
  std::vector<lsys::Rule> rules;
  std::array<std::vector<int>, 256> by_symbol;  // rule indices per predecessor symbol
  std::array<bool, 256> ignored{};
  bool any_context = false;

  ModuleString step(const ModuleString& word, int iteration, std::uint64_t seed, std::size_t max_modules,
                    const std::function<bool()>& should_stop) const;
  bool match_left(const lsys::Rule& r, const ModuleString& w, const std::vector<std::int32_t>& match, std::size_t i,
                  double* vars) const;
  bool match_right(const lsys::Rule& r, std::size_t p, const ModuleString& w, const std::vector<std::int32_t>& match,
                   std::size_t j, double* vars) const;
};

LSystem::LSystem(const std::string& axiom, const std::string& rules, const std::string& ignore)
    : impl_(std::make_unique<Impl>()) {
  for (char c : ignore)
    if (!std::isspace(static_cast<unsigned char>(c))) impl_->ignored[static_cast<unsigned char>(c)] = true;
  lsys::Grammar g = lsys::parse_grammar(axiom, rules);
  impl_->axiom = std::move(g.axiom);
  impl_->rules = std::move(g.rules);
  for (std::size_t k = 0; k < impl_->rules.size(); ++k) {
    const lsys::Rule& r = impl_->rules[k];
    impl_->any_context = impl_->any_context || r.has_context();
    impl_->by_symbol[static_cast<unsigned char>(r.pred.symbol)].push_back(static_cast<int>(k));
  }
}

LSystem::~LSystem() = default;
LSystem::LSystem(LSystem&&) noexcept = default;
LSystem& LSystem::operator=(LSystem&&) noexcept = default;
std::size_t LSystem::rule_count() const { return impl_->rules.size(); }

std::size_t LSystem::max_module_parameters() const {
  std::size_t most = 0;
  for (const auto& t : impl_->axiom) most = std::max(most, t.args.size());
  for (const auto& r : impl_->rules)
    for (const auto& t : r.successor) most = std::max(most, t.args.size());
  return most;
}

std::uint64_t LSystem::max_word_length(int iterations, std::uint64_t cap) const {
  // Only the symbols that occur: the axiom's and every successor's.
  std::vector<unsigned char> symbols;
  std::array<int, 256> slot;
  slot.fill(-1);
  const auto note = [&](char c) {
    const auto u = static_cast<unsigned char>(c);
    if (slot[u] < 0) {
      slot[u] = static_cast<int>(symbols.size());
      symbols.push_back(u);
    }
  };
  for (const auto& t : impl_->axiom) note(t.symbol);
  for (const auto& r : impl_->rules) {
    note(r.pred.symbol);
    for (const auto& t : r.successor) note(t.symbol);
  }
  const std::size_t n = symbols.size();
  // The parameter counts each symbol's modules are made with: a rule matches only modules of its predecessor's.
  std::vector<std::vector<std::size_t>> arities(n);
  const auto made = [&](const lsys::Template& t) {
    auto& a = arities[static_cast<std::size_t>(slot[static_cast<unsigned char>(t.symbol)])];
    if (std::find(a.begin(), a.end(), t.args.size()) == a.end()) a.push_back(t.args.size());
  };
  for (const auto& t : impl_->axiom) made(t);
  for (const auto& r : impl_->rules)
    for (const auto& t : r.successor) made(t);
  // grow[s][t]: the most modules of t one module of s becomes.
  std::vector<double> grow(n * n, 0.0);
  for (std::size_t s = 0; s < n; ++s) {
    const auto& list = impl_->by_symbol[symbols[s]];
    bool always = false;  // some rule always applies (no condition, no context, the only alternative)
    for (const int k : list) {
      const lsys::Rule& r = impl_->rules[static_cast<std::size_t>(k)];
      std::vector<double> count(n, 0.0);
      for (const auto& t : r.successor)
        count[static_cast<std::size_t>(slot[static_cast<unsigned char>(t.symbol)])] += 1;
      for (std::size_t t = 0; t < n; ++t) grow[s * n + t] = std::max(grow[s * n + t], count[t]);
      bool every_arity = true;
      for (const std::size_t a : arities[s]) every_arity = every_arity && a == r.pred.slots.size();
      always = always || (list.size() == 1 && !r.has_context() && !r.condition && every_arity);
    }
    if (!always) grow[s * n + s] = std::max(grow[s * n + s], 1.0);
  }
  std::vector<double> counts(n, 0.0), next(n);
  for (const auto& t : impl_->axiom) counts[static_cast<std::size_t>(slot[static_cast<unsigned char>(t.symbol)])] += 1;
  const auto total = [&] {
    double sum = 0.0;
    for (const double c : counts) sum += c;
    return sum;
  };
  for (int it = 0; it < iterations && total() < static_cast<double>(cap); ++it) {
    std::fill(next.begin(), next.end(), 0.0);
    for (std::size_t s = 0; s < n; ++s)
      if (counts[s] > 0.0)
        for (std::size_t t = 0; t < n; ++t) next[t] += counts[s] * grow[s * n + t];
    counts.swap(next);
  }
  return static_cast<std::uint64_t>(std::min(total(), static_cast<double>(cap)));
}

std::uint64_t derive_peak_bytes(std::size_t max_modules, std::size_t parameters) {
  const std::uint64_t module = sizeof(char) + sizeof(std::uint32_t) + parameters * sizeof(float);
  const std::uint64_t word = 2 * module * max_modules;  // a vector may hold up to twice what it uses
  return 2 * word + sizeof(std::int32_t) * static_cast<std::uint64_t>(max_modules);
}

ModuleString LSystem::axiom(std::uint64_t seed) const {
  ModuleString w;
  Draws draws{seed, -1, 0, 1};
  float values[kMaxParams];
  for (std::size_t k = 0; k < impl_->axiom.size(); ++k) {
    const auto& m = impl_->axiom[k];
    draws.module = k;
    draws.counter = 1;
    for (std::size_t a = 0; a < m.args.size(); ++a) values[a] = static_cast<float>(eval(m.args[a], nullptr, draws));
    w.append(m.symbol, std::span<const float>(values, m.args.size()));
  }
  return w;
}

bool LSystem::Impl::match_left(const Rule& r, const ModuleString& w, const std::vector<std::int32_t>& match,
                               std::size_t i, double* vars) const {
  std::ptrdiff_t j = static_cast<std::ptrdiff_t>(i) - 1;
  for (std::ptrdiff_t p = static_cast<std::ptrdiff_t>(r.left.size()) - 1; p >= 0; --p) {
    for (;;) {
      if (j < 0) return false;
      const char c = w.symbols[static_cast<std::size_t>(j)];
      if (c == ']')
        j = match[static_cast<std::size_t>(j)] - 1;  // a sibling branch: skip it whole
      else if (c == '[' || ignored[static_cast<unsigned char>(c)])
        --j;  // '[': step out to the parent
      else
        break;
    }
    const Pattern& pat = r.left[static_cast<std::size_t>(p)];
    const auto k = static_cast<std::size_t>(j);
    if (w.symbols[k] != pat.symbol || w.param_count(k) != pat.slots.size()) return false;
    for (std::size_t a = 0; a < pat.slots.size(); ++a) vars[pat.slots[a]] = w.params[w.offsets[k] + a];
    --j;
  }
  return true;
}

bool LSystem::Impl::match_right(const Rule& r, std::size_t p, const ModuleString& w,
                                const std::vector<std::int32_t>& match, std::size_t j, double* vars) const {
  const std::size_t n = w.size();
  for (; p < r.right.size(); ++p) {
    const Pattern& pat = r.right[p];
    if (pat.symbol == ']') {
      // The rest of the current branch of the word is skipped, through its closing ']'.
      for (;;) {
        if (j >= n) return false;
        const char c = w.symbols[j];
        if (c == '[')
          j = static_cast<std::size_t>(match[j]) + 1;
        else if (c == ']') {
          ++j;
          break;
        } else
          ++j;
      }
      continue;
    }
    while (j < n && ignored[static_cast<unsigned char>(w.symbols[j])]) ++j;
    if (pat.symbol == '[') {
      // Try each branch that starts here in turn.
      while (j < n && w.symbols[j] == '[') {
        if (match_right(r, p + 1, w, match, j + 1, vars)) return true;
        j = static_cast<std::size_t>(match[j]) + 1;
        while (j < n && ignored[static_cast<unsigned char>(w.symbols[j])]) ++j;
      }
      return false;
    }
    for (;;) {  // branches between modules of the pattern are skipped
      while (j < n && ignored[static_cast<unsigned char>(w.symbols[j])]) ++j;
      if (j < n && w.symbols[j] == '[')
        j = static_cast<std::size_t>(match[j]) + 1;
      else
        break;
    }
    if (j >= n || w.symbols[j] != pat.symbol || w.param_count(j) != pat.slots.size()) return false;
    for (std::size_t a = 0; a < pat.slots.size(); ++a) vars[pat.slots[a]] = w.params[w.offsets[j] + a];
    ++j;
  }
  return true;
}

ModuleString LSystem::Impl::step(const ModuleString& w, int iteration, std::uint64_t seed, std::size_t max_modules,
                                 const std::function<bool()>& should_stop) const {
  const std::size_t n = w.size();
  std::vector<std::int32_t> match;
  if (any_context) {
    // Matching brackets of the word (an unmatched one matches the word's end).
    match.assign(n, static_cast<std::int32_t>(n));
    std::vector<std::int32_t> stack;
    for (std::size_t k = 0; k < n; ++k) {
      if (w.symbols[k] == '[')
        stack.push_back(static_cast<std::int32_t>(k));
      else if (w.symbols[k] == ']') {
        if (stack.empty())
          match[k] = -1;
        else {
          match[k] = stack.back();
          match[static_cast<std::size_t>(stack.back())] = static_cast<std::int32_t>(k);
          stack.pop_back();
        }
      }
    }
  }
  ModuleString out;
  out.symbols.reserve(n * 2);
  out.offsets.reserve(n * 2 + 1);
  out.params.reserve(w.params.size() * 2);
  double vars[kMaxSlots];
  struct Candidate {
    int rule;
    double weight;
  };
  std::vector<Candidate> candidates;
  float values[kMaxParams];
  for (std::size_t i = 0; i < n; ++i) {
    if ((i & 4095) == 4095 && should_stop && should_stop()) break;
    const char sym = w.symbols[i];
    const auto& list = by_symbol[static_cast<unsigned char>(sym)];
    const Rule* chosen = nullptr;
    Draws draws{seed, iteration, i, 1};
    if (!list.empty()) {
      candidates.clear();
      const std::size_t np = w.param_count(i);
      bool context = false;
      for (int ri : list) {
        const Rule& r = rules[static_cast<std::size_t>(ri)];
        if (r.pred.slots.size() != np) continue;
        if (context && !r.has_context()) continue;
        if (!r.left.empty() && !match_left(r, w, match, i, vars)) continue;
        if (!r.right.empty() && !match_right(r, 0, w, match, i + 1, vars)) continue;
        for (std::size_t a = 0; a < np; ++a) vars[r.pred.slots[a]] = w.params[w.offsets[i] + a];
        if (r.condition && eval(*r.condition, vars, draws) == 0.0) continue;
        const double weight = eval(r.weight, vars, draws);
        if (!(weight > 0.0)) continue;
        if (r.has_context() && !context) {
          context = true;
          candidates.clear();
        }
        candidates.push_back({ri, weight});
      }
      if (candidates.size() == 1) {
        chosen = &rules[static_cast<std::size_t>(candidates[0].rule)];
      } else if (candidates.size() > 1) {
        double total = 0.0;
        for (const auto& c : candidates) total += c.weight;
        double u = unit_double(draw_key(seed, iteration, i, 0)) * total;
        chosen = &rules[static_cast<std::size_t>(candidates.back().rule)];
        for (const auto& c : candidates) {
          if (u < c.weight) {
            chosen = &rules[static_cast<std::size_t>(c.rule)];
            break;
          }
          u -= c.weight;
        }
      }
    }
    if (!chosen) {
      out.append(sym, w.params_of(i));
    } else {
      // Rebind: the parameters of the chosen rule (another candidate may have overwritten the slots).
      const Rule& r = *chosen;
      if (!r.left.empty()) match_left(r, w, match, i, vars);
      if (!r.right.empty()) match_right(r, 0, w, match, i + 1, vars);
      for (std::size_t a = 0; a < r.pred.slots.size(); ++a) vars[r.pred.slots[a]] = w.params[w.offsets[i] + a];
      for (const Template& m : r.successor) {
        for (std::size_t a = 0; a < m.args.size(); ++a) values[a] = static_cast<float>(eval(m.args[a], vars, draws));
        out.append(m.symbol, std::span<const float>(values, m.args.size()));
      }
    }
    if (out.size() > max_modules)
      throw LSystemError("derivation", 0, 0,
                         "the word exceeds max_modules (" + std::to_string(max_modules) + ") at iteration " +
                             std::to_string(iteration + 1));
  }
  return out;
}

ModuleString LSystem::step(const ModuleString& word, int iteration, std::uint64_t seed, std::size_t max_modules) const {
  return impl_->step(word, iteration, seed, max_modules, {});
}

ModuleString LSystem::derive(const DeriveOptions& o) const {
  ModuleString w = axiom(o.seed);
  if (w.size() > o.max_modules)
    throw LSystemError("derivation", 0, 0, "the axiom exceeds max_modules (" + std::to_string(o.max_modules) + ")");
  for (int it = 0; it < o.iterations; ++it) {
    if (o.should_stop && o.should_stop()) return w;
    w = impl_->step(w, it, o.seed, o.max_modules, o.should_stop);
    if (o.progress) o.progress(static_cast<double>(it + 1) / o.iterations);
  }
  return w;
}

std::string derive_text(const std::string& axiom, const std::string& rules, int iterations, std::uint64_t seed,
                        const std::string& ignore) {
  const LSystem l(axiom, rules, ignore);
  DeriveOptions o;
  o.iterations = iterations;
  o.seed = seed;
  return l.derive(o).text();
}

}  // namespace orogen::plants
