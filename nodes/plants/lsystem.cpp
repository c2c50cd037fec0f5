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
using lsys::Expr;
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
  std::array<bool, 256> ignored{};
  bool any_context = false;

  // A successor whose arguments are all constants, laid out as it is written: copied, not evaluated.
  struct Block {
    std::vector<char> symbols;
    std::vector<std::uint32_t> ends;  // each module's parameter end, counted from the block's first parameter
    std::vector<float> params;
  };
  std::vector<Block> blocks;          // per rule
  std::vector<bool> constant_blocks;  // per rule: its successor is blocks[rule]

  struct Candidate {
    int rule;
    double weight;
  };
  // What a module of a symbol becomes, decided once per grammar. `fixed`: the symbol's rules all take `arity`
  // parameters and have neither context nor condition, and constant weights; for a module of that arity the
  // candidates are then the same for every module (those of positive weight, in the order of the text), so no
  // rule is matched or weighed per module. Anything else (other symbols, other arities) goes the general way.
  struct SymbolPlan {
    std::vector<int> list;  // the indices of the rules for the symbol, in the order of the text
    bool fixed = false;
    std::size_t arity = 0;
    std::vector<Candidate> candidates;  // fixed: the candidates, in rule order
    double total = 0.0;                 // fixed: their weights' sum, added in that order
  };
  std::vector<SymbolPlan> plans;  // [0]: the plan of every symbol without rules (copied)
  // Per symbol, looked up for every module: the plan's block and the bounds that size a step's output.
  struct SymbolEntry {
    const Block* block = nullptr;                     // fixed with a single, constant candidate: its successor
    std::uint32_t arity = 0;                          // of the plan
    std::uint32_t most_modules = 1, most_params = 0;  // what one module can become (its copy or any successor)
    std::uint8_t plan = 0;                            // index in plans
  };
  std::array<SymbolEntry, 256> entries;
  const std::vector<int>& rules_for(char symbol) const {
    return plans[entries[static_cast<unsigned char>(symbol)].plan].list;
  }

  void plan();
  void write_axiom(std::uint64_t seed, ModuleString& w) const;
  void step(const ModuleString& word, ModuleString& out, int iteration, std::uint64_t seed, std::size_t max_modules,
            const std::function<bool()>& should_stop) const;
  const Rule* choose(const ModuleString& w, const std::vector<std::int32_t>& match, std::size_t i, int iteration,
                     std::uint64_t seed, double* vars, Draws& draws, std::vector<Candidate>& candidates) const;
  bool match_left(const lsys::Rule& r, const ModuleString& w, const std::vector<std::int32_t>& match, std::size_t i,
                  double* vars) const;
  bool match_right(const lsys::Rule& r, std::size_t p, const ModuleString& w, const std::vector<std::int32_t>& match,
                   std::size_t j, double* vars) const;
};

void LSystem::Impl::plan() {
  blocks.assign(rules.size(), {});
  constant_blocks.assign(rules.size(), false);
  for (std::size_t k = 0; k < rules.size(); ++k) {
    const Rule& r = rules[k];
    bool constant = true;
    Block& b = blocks[k];
    for (const Template& m : r.successor) {
      b.symbols.push_back(m.symbol);
      for (const auto& a : m.args) {
        constant = constant && a.constant();
        // eval() of a constant returns its value; the word stores it as float, as the general path does.
        b.params.push_back(a.constant() ? static_cast<float>(a.code[0].value) : 0.0f);
      }
      b.ends.push_back(static_cast<std::uint32_t>(b.params.size()));
    }
    constant_blocks[k] = constant;
  }
  plans.assign(1, SymbolPlan{});
  for (std::size_t k = 0; k < rules.size(); ++k) {
    SymbolEntry& e = entries[static_cast<unsigned char>(rules[k].pred.symbol)];
    if (e.plan == 0) {  // symbols are printable ASCII: fewer than 256 plans
      e.plan = static_cast<std::uint8_t>(plans.size());
      plans.emplace_back();
    }
    plans[e.plan].list.push_back(static_cast<int>(k));
  }
  for (std::size_t c = 0; c < 256; ++c) {
    SymbolEntry& e = entries[c];
    if (e.plan == 0) continue;
    SymbolPlan& p = plans[e.plan];
    const auto& list = p.list;
    p.fixed = true;
    for (const int k : list) {
      const Rule& r = rules[static_cast<std::size_t>(k)];
      e.most_modules = std::max(e.most_modules, static_cast<std::uint32_t>(r.successor.size()));
      e.most_params =
          std::max(e.most_params, static_cast<std::uint32_t>(blocks[static_cast<std::size_t>(k)].params.size()));
      p.fixed = p.fixed && !r.has_context() && !r.condition && r.weight.constant() &&
                r.pred.slots.size() == rules[static_cast<std::size_t>(list.front())].pred.slots.size();
    }
    if (!p.fixed) continue;
    p.arity = rules[static_cast<std::size_t>(list.front())].pred.slots.size();
    e.arity = static_cast<std::uint32_t>(p.arity);
    for (const int k : list) {
      // The general path's test: a weight that is not > 0 (0, or NaN) drops the rule.
      const double weight = rules[static_cast<std::size_t>(k)].weight.code[0].value;
      if (weight > 0.0) p.candidates.push_back({k, weight});
    }
    for (const Candidate& d : p.candidates) p.total += d.weight;
    if (p.candidates.size() == 1 && constant_blocks[static_cast<std::size_t>(p.candidates[0].rule)])
      e.block = &blocks[static_cast<std::size_t>(p.candidates[0].rule)];
  }
}

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
  }
  impl_->plan();
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
    const auto& list = impl_->rules_for(static_cast<char>(symbols[s]));
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
  impl_->write_axiom(seed, w);
  return w;
}

void LSystem::Impl::write_axiom(std::uint64_t seed, ModuleString& w) const {
  w.clear();
  Draws draws{seed, -1, 0, 1};
  float values[kMaxParams];
  for (std::size_t k = 0; k < axiom.size(); ++k) {
    const auto& m = axiom[k];
    draws.module = k;
    draws.counter = 1;
    for (std::size_t a = 0; a < m.args.size(); ++a) values[a] = static_cast<float>(eval(m.args[a], nullptr, draws));
    w.append(m.symbol, std::span<const float>(values, m.args.size()));
  }
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

// Rule selection for module i in general: the rules of its symbol whose arity, contexts and condition match; the
// context-sensitive ones take precedence; the roulette of the weights picks one. Returns nullptr when none
// applies (the module is copied); otherwise `vars` holds the chosen rule's parameters and `draws` has counted the
// draws that conditions and weights made.
const Rule* LSystem::Impl::choose(const ModuleString& w, const std::vector<std::int32_t>& match, std::size_t i,
                                  int iteration, std::uint64_t seed, double* vars, Draws& draws,
                                  std::vector<Candidate>& candidates) const {
  const auto& list = rules_for(w.symbols[i]);
  const Rule* chosen = nullptr;
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
  if (chosen) {
    // Rebind: the parameters of the chosen rule (another candidate may have overwritten the slots).
    const Rule& r = *chosen;
    if (!r.left.empty()) match_left(r, w, match, i, vars);
    if (!r.right.empty()) match_right(r, 0, w, match, i + 1, vars);
    for (std::size_t a = 0; a < r.pred.slots.size(); ++a) vars[r.pred.slots[a]] = w.params[w.offsets[i] + a];
  }
  return chosen;
}

void LSystem::Impl::step(const ModuleString& w, ModuleString& out, int iteration, std::uint64_t seed,
                         std::size_t max_modules, const std::function<bool()>& should_stop) const {
  const std::size_t n = w.size();
  const char* in_symbols = w.symbols.data();
  const std::uint32_t* in_offsets = w.offsets.data();
  const float* in_params = w.params.data();

  // Size the output once, from what each module can become: exact for deterministic context-free grammars, an
  // upper bound otherwise (within the memory the node declares: max_word_length counts the same way). No
  // growth, no copy while writing.
  std::size_t most_modules = 0, most_params = 0, widest = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const auto c = static_cast<unsigned char>(in_symbols[i]);
    const std::size_t np = in_offsets[i + 1] - in_offsets[i];
    most_modules += entries[c].most_modules;
    most_params += std::max<std::size_t>(np, entries[c].most_params);
    widest = std::max(widest, std::max<std::size_t>(np, entries[c].most_params));
  }
  // Past max_modules the step fails, so no more room is ever needed.
  const std::size_t capacity = std::min(most_modules, max_modules);
  out.symbols.resize(capacity);
  out.offsets.resize(capacity + 1);
  out.params.resize(std::min(most_params, capacity * widest));
  char* symbols = out.symbols.data();
  std::uint32_t* offsets = out.offsets.data();
  float* params = out.params.data();
  offsets[0] = 0;
  std::size_t m = 0, q = 0;  // modules and parameters written
  const auto write_block = [&](const Block& b) {
    const std::size_t len = b.symbols.size();
    std::copy_n(b.symbols.data(), len, symbols + m);
    const auto base = static_cast<std::uint32_t>(q);
    for (std::size_t k = 0; k < len; ++k) offsets[m + 1 + k] = base + b.ends[k];
    std::copy_n(b.params.data(), b.params.size(), params + q);
    m += len;
    q += b.params.size();
  };
  const auto too_long = [&] {
    return LSystemError("derivation", 0, 0,
                        "the word exceeds max_modules (" + std::to_string(max_modules) + ") at iteration " +
                            std::to_string(iteration + 1));
  };

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
  double vars[kMaxSlots];
  std::vector<Candidate> candidates;
  for (std::size_t i = 0; i < n; ++i) {
    if ((i & 4095) == 4095 && should_stop && should_stop()) break;
    const char sym = in_symbols[i];
    const SymbolEntry& e = entries[static_cast<unsigned char>(sym)];
    const std::uint32_t first = in_offsets[i];
    const std::size_t np = in_offsets[i + 1] - first;
    if (e.block && np == e.arity) {
      // The common case of context-free grammars: one rule, constant successor, copied as a block.
      if (m + e.block->symbols.size() > max_modules) throw too_long();
      write_block(*e.block);
      continue;
    }
    const SymbolPlan& p = plans[e.plan];
    const Rule* chosen = nullptr;
    Draws draws{seed, iteration, i, 1};
    if (p.fixed && np == p.arity) {
      // The candidates are known: only the roulette remains, drawn as choose() draws it.
      if (p.candidates.size() == 1) {
        chosen = &rules[static_cast<std::size_t>(p.candidates[0].rule)];
      } else if (p.candidates.size() > 1) {
        double u = unit_double(draw_key(seed, iteration, i, 0)) * p.total;
        chosen = &rules[static_cast<std::size_t>(p.candidates.back().rule)];
        for (const auto& c : p.candidates) {
          if (u < c.weight) {
            chosen = &rules[static_cast<std::size_t>(c.rule)];
            break;
          }
          u -= c.weight;
        }
      }
      if (chosen)
        for (std::size_t a = 0; a < np; ++a) vars[chosen->pred.slots[a]] = in_params[first + a];
    } else if (e.plan != 0) {
      chosen = choose(w, match, i, iteration, seed, vars, draws, candidates);
    }
    if (!chosen) {
      if (m + 1 > max_modules) throw too_long();
      symbols[m] = sym;
      for (std::size_t a = 0; a < np; ++a) params[q + a] = in_params[first + a];  // short: no memmove call
      q += np;
      offsets[++m] = static_cast<std::uint32_t>(q);
      continue;
    }
    const auto k = static_cast<std::size_t>(chosen - rules.data());
    if (m + chosen->successor.size() > max_modules) throw too_long();
    if (constant_blocks[k]) {
      write_block(blocks[k]);
      continue;
    }
    for (const Template& t : chosen->successor) {
      symbols[m] = t.symbol;
      for (const Expr& e : t.args) params[q++] = static_cast<float>(eval(e, vars, draws));
      offsets[++m] = static_cast<std::uint32_t>(q);
    }
  }
  out.symbols.resize(m);
  out.offsets.resize(m + 1);
  out.params.resize(q);
}

ModuleString LSystem::step(const ModuleString& word, int iteration, std::uint64_t seed, std::size_t max_modules) const {
  ModuleString out;
  impl_->step(word, out, iteration, seed, max_modules, {});
  return out;
}

void LSystem::step(const ModuleString& word, ModuleString& out, int iteration, std::uint64_t seed,
                   std::size_t max_modules) const {
  impl_->step(word, out, iteration, seed, max_modules, {});
}

ModuleString LSystem::derive(const DeriveOptions& o) const {
  ModuleString word, spare;
  derive(o, word, spare);
  spare = ModuleString();  // freed before any trimming copy
  // Steps are sized by what each module can become; a word kept (a node's output) gives back a notable excess
  // (conditions or stochastic choices that picked shorter successors).
  const auto trim = [](auto& v) {
    if (v.capacity() - v.size() > v.size() / 8) v.shrink_to_fit();
  };
  trim(word.symbols);
  trim(word.offsets);
  trim(word.params);
  return word;
}

void LSystem::derive(const DeriveOptions& o, ModuleString& word, ModuleString& spare) const {
  impl_->write_axiom(o.seed, word);
  if (word.size() > o.max_modules)
    throw LSystemError("derivation", 0, 0, "the axiom exceeds max_modules (" + std::to_string(o.max_modules) + ")");
  for (int it = 0; it < o.iterations; ++it) {
    if (o.should_stop && o.should_stop()) return;
    impl_->step(word, spare, it, o.seed, o.max_modules, o.should_stop);
    std::swap(word, spare);
    if (o.progress) o.progress(static_cast<double>(it + 1) / o.iterations);
  }
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
