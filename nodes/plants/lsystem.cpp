#include "nodes/plants/lsystem.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <map>
#include <numbers>
#include <optional>
#include <string_view>
#include <vector>

#include "nodes/common/hash.h"

namespace orogen::plants {

LSystemError::LSystemError(const std::string& where_, int line_, int column_, const std::string& what)
    : std::invalid_argument(where_ + (line_ > 0 ? " line " + std::to_string(line_) : std::string()) +
                            (column_ > 0 ? ", column " + std::to_string(column_) : std::string()) + ": " + what),
      where(where_), line(line_), column(column_) {}

namespace {

constexpr int kMaxParams = 16;  // per module
constexpr int kMaxSlots = 64;   // formal parameters per rule

// --- counter-based random numbers ----------------------------------------------------------------------------

inline std::uint64_t draw_key(std::uint64_t seed, int iteration, std::size_t module, std::uint32_t draw) {
  std::uint64_t h = mix64(seed + kGoldenGamma);
  h = mix64(h ^ (static_cast<std::uint64_t>(static_cast<std::uint32_t>(iteration)) << 32 | draw));
  return mix64(h ^ (static_cast<std::uint64_t>(module) * 0xD6E8FEB86659FD93ull));
}

struct Draws {
  std::uint64_t seed = 0;
  int iteration = 0;
  std::size_t module = 0;
  std::uint32_t counter = 1;  // 0 is the roulette's draw
  double uniform() { return unit_double(draw_key(seed, iteration, module, counter++)); }
};

// --- source text with positions -------------------------------------------------------------------------------

// The text with typographic symbols replaced by ASCII (→ ->, − -, × *, ≤ <=, ≥ >=) and, per byte, the
// position (line, column) in the original.
struct Source {
  std::string where;
  std::string text;
  std::vector<std::pair<int, int>> pos;  // per byte of text, plus one past the end
  bool lines = true;

  Source(std::string where_, const std::string& original, bool lines_) : where(std::move(where_)), lines(lines_) {
    int line = 1, col = 1;
    auto push = [&](std::string_view s, int l, int c) {
      for (char ch : s) {
        text.push_back(ch);
        pos.emplace_back(l, c);
      }
    };
    for (std::size_t i = 0; i < original.size();) {
      const std::string_view rest(original.data() + i, original.size() - i);
      struct Sub {
        std::string_view from, to;
      };
      static constexpr Sub subs[] = {{"\u2192", "->"}, {"\u2212", "-"}, {"\u00d7", "*"},
                                     {"\u2264", "<="}, {"\u2265", ">="}, {"\u2260", "!="}};
      bool done = false;
      for (const auto& s : subs)
        if (rest.starts_with(s.from)) {
          push(s.to, line, col);
          i += s.from.size();
          ++col;
          done = true;
          break;
        }
      if (done) continue;
      const char c = original[i];
      push(std::string_view(&c, 1), line, col);
      if (c == '\n') {
        ++line;
        col = 1;
      } else if ((static_cast<unsigned char>(c) & 0xC0) != 0x80) {
        ++col;  // count UTF-8 lead bytes only
      }
      ++i;
    }
    pos.emplace_back(line, col);
  }

  [[noreturn]] void fail(std::size_t at, const std::string& what) const {
    const auto [l, c] = pos[std::min(at, pos.size() - 1)];
    throw LSystemError(where, lines ? l : 0, c, what);
  }
};

// --- expressions ------------------------------------------------------------------------------------------------

enum class Op : std::uint8_t {
  Const, Var, Add, Sub, Mul, Div, Pow, Neg, Not, Lt, Le, Gt, Ge, Eq, Ne, And, Or,
  Sin, Cos, Tan, Asin, Acos, Atan, Atan2, Sqrt, Abs, Min, Max, Floor, Ceil, Exp, Log, Clamp, Uniform, Gauss
};

struct Instr {
  Op op;
  int slot = 0;
  double value = 0.0;
};

struct Expr {
  std::vector<Instr> code;
  bool constant() const { return code.size() == 1 && code[0].op == Op::Const; }
};

constexpr double kDeg = std::numbers::pi / 180.0;

double eval(const Expr& e, const double* vars, Draws& draws) {
  if (e.constant()) return e.code[0].value;
  double stack[64];
  int sp = 0;
  for (const Instr& in : e.code) {
    switch (in.op) {
      case Op::Const: stack[sp++] = in.value; break;
      case Op::Var: stack[sp++] = vars[in.slot]; break;
#define BIN(OP, EXPR)            \
  case Op::OP: {                 \
    const double b = stack[--sp]; \
    const double a = stack[sp - 1]; \
    stack[sp - 1] = (EXPR);      \
    break;                       \
  }
      BIN(Add, a + b)
      BIN(Sub, a - b)
      BIN(Mul, a * b)
      BIN(Div, a / b)
      BIN(Pow, std::pow(a, b))
      BIN(Lt, a < b ? 1.0 : 0.0)
      BIN(Le, a <= b ? 1.0 : 0.0)
      BIN(Gt, a > b ? 1.0 : 0.0)
      BIN(Ge, a >= b ? 1.0 : 0.0)
      BIN(Eq, a == b ? 1.0 : 0.0)
      BIN(Ne, a != b ? 1.0 : 0.0)
      BIN(And, (a != 0.0 && b != 0.0) ? 1.0 : 0.0)
      BIN(Or, (a != 0.0 || b != 0.0) ? 1.0 : 0.0)
      BIN(Atan2, std::atan2(a, b) / kDeg)
      BIN(Min, std::min(a, b))
      BIN(Max, std::max(a, b))
      BIN(Uniform, a + (b - a) * draws.uniform())
      BIN(Gauss, a + b * std::sqrt(-2.0 * std::log(1.0 - draws.uniform())) *
                         std::cos(2.0 * std::numbers::pi * draws.uniform()))
#undef BIN
#define UN(OP, EXPR)           \
  case Op::OP: {               \
    const double a = stack[sp - 1]; \
    stack[sp - 1] = (EXPR);    \
    break;                     \
  }
      UN(Neg, -a)
      UN(Not, a == 0.0 ? 1.0 : 0.0)
      UN(Sin, std::sin(a * kDeg))
      UN(Cos, std::cos(a * kDeg))
      UN(Tan, std::tan(a * kDeg))
      UN(Asin, std::asin(a) / kDeg)
      UN(Acos, std::acos(a) / kDeg)
      UN(Atan, std::atan(a) / kDeg)
      UN(Sqrt, std::sqrt(a))
      UN(Abs, std::abs(a))
      UN(Floor, std::floor(a))
      UN(Ceil, std::ceil(a))
      UN(Exp, std::exp(a))
      UN(Log, std::log(a))
#undef UN
      case Op::Clamp: {
        const double hi = stack[--sp], lo = stack[--sp];
        stack[sp - 1] = std::clamp(stack[sp - 1], lo, hi);
        break;
      }
    }
  }
  return stack[0];
}

struct Function {
  std::string_view name;
  Op op;
  int arity;
};
constexpr Function kFunctions[] = {
    {"sin", Op::Sin, 1},     {"cos", Op::Cos, 1},       {"tan", Op::Tan, 1},   {"asin", Op::Asin, 1},
    {"acos", Op::Acos, 1},   {"atan", Op::Atan, 1},     {"atan2", Op::Atan2, 2}, {"sqrt", Op::Sqrt, 1},
    {"abs", Op::Abs, 1},     {"min", Op::Min, 2},       {"max", Op::Max, 2},   {"floor", Op::Floor, 1},
    {"ceil", Op::Ceil, 1},   {"exp", Op::Exp, 1},       {"log", Op::Log, 1},   {"pow", Op::Pow, 2},
    {"clamp", Op::Clamp, 3}, {"uniform", Op::Uniform, 2}, {"U", Op::Uniform, 2}, {"gauss", Op::Gauss, 2},
    {"N", Op::Gauss, 2},
};

bool ident_start(char c) { return std::isalpha(static_cast<unsigned char>(c)) || c == '_' || (c & 0x80); }
bool ident_char(char c) { return ident_start(c) || std::isdigit(static_cast<unsigned char>(c)); }

// Recursive-descent expression compiler over src.text[pos, end).
class ExprParser {
 public:
  ExprParser(const Source& src, std::size_t pos, std::size_t end, const std::map<std::string, int>& vars,
             const std::map<std::string, double>& constants)
      : s_(src), p_(pos), end_(end), vars_(vars), constants_(constants) {}

  Expr parse_all() {
    Expr e;
    code_ = &e.code;
    parse_or();
    skip();
    if (p_ < end_) s_.fail(p_, std::string("unexpected '") + s_.text[p_] + "' in expression");
    fold(e);
    return e;
  }

 private:
  void skip() {
    while (p_ < end_ && std::isspace(static_cast<unsigned char>(s_.text[p_]))) ++p_;
  }
  bool accept(std::string_view tok) {
    skip();
    if (s_.text.compare(p_, tok.size(), tok) == 0 && p_ + tok.size() <= end_) {
      p_ += tok.size();
      return true;
    }
    return false;
  }
  void emit(Op op, double v = 0.0, int slot = 0) {
    code_->push_back({op, slot, v});
    depth_ += (op == Op::Const || op == Op::Var) ? 1 : 0;
    max_depth_ = std::max(max_depth_, depth_);
    if (max_depth_ > 60) s_.fail(p_, "expression too deeply nested");
  }
  void pop(int n) { depth_ -= n; }

  void parse_or() {
    parse_and();
    while (accept("||")) parse_and(), emit(Op::Or), pop(1);
  }
  void parse_and() {
    parse_cmp();
    while (accept("&&")) parse_cmp(), emit(Op::And), pop(1);
  }
  void parse_cmp() {
    parse_add();
    for (;;) {
      Op op;
      if (accept("<=")) op = Op::Le;
      else if (accept(">=")) op = Op::Ge;
      else if (accept("==")) op = Op::Eq;
      else if (accept("!=")) op = Op::Ne;
      else if (accept("<")) op = Op::Lt;
      else if (accept(">")) op = Op::Gt;
      else return;
      parse_add();
      emit(op), pop(1);
    }
  }
  void parse_add() {
    parse_mul();
    for (;;) {
      if (accept("+")) parse_mul(), emit(Op::Add), pop(1);
      else if (accept("-")) parse_mul(), emit(Op::Sub), pop(1);
      else return;
    }
  }
  void parse_mul() {
    parse_unary();
    for (;;) {
      if (accept("*")) parse_unary(), emit(Op::Mul), pop(1);
      else if (accept("/")) parse_unary(), emit(Op::Div), pop(1);
      else return;
    }
  }
  void parse_unary() {
    if (accept("-")) return parse_unary(), emit(Op::Neg);
    if (accept("+")) return parse_unary();
    if (accept("!")) return parse_unary(), emit(Op::Not);
    parse_pow();
  }
  void parse_pow() {
    parse_primary();
    if (accept("^")) parse_unary(), emit(Op::Pow), pop(1);  // right-associative
  }
  void parse_primary() {
    skip();
    if (p_ >= end_) s_.fail(p_, "expression expected");
    const char c = s_.text[p_];
    if (c == '(') {
      ++p_;
      parse_or();
      if (!accept(")")) s_.fail(p_, "')' expected");
      return;
    }
    if (std::isdigit(static_cast<unsigned char>(c)) || c == '.') {
      double v = 0.0;
      const char* b = s_.text.data() + p_;
      const auto r = std::from_chars(b, s_.text.data() + end_, v);
      if (r.ec != std::errc()) s_.fail(p_, "invalid number");
      p_ += static_cast<std::size_t>(r.ptr - b);
      emit(Op::Const, v);
      return;
    }
    if (ident_start(c)) {
      const std::size_t at = p_;
      while (p_ < end_ && ident_char(s_.text[p_])) ++p_;
      const std::string name = s_.text.substr(at, p_ - at);
      skip();
      if (p_ < end_ && s_.text[p_] == '(') {
        const Function* f = nullptr;
        for (const auto& fn : kFunctions)
          if (fn.name == name) f = &fn;
        if (!f) s_.fail(at, "unknown function '" + name + "'");
        ++p_;
        for (int k = 0; k < f->arity; ++k) {
          if (k > 0 && !accept(",")) s_.fail(p_, "',' expected: " + name + " takes " + std::to_string(f->arity) + " arguments");
          parse_or();
        }
        if (!accept(")")) s_.fail(p_, "')' expected: " + name + " takes " + std::to_string(f->arity) + " arguments");
        emit(f->op), pop(f->arity - 1);
        return;
      }
      if (auto it = vars_.find(name); it != vars_.end()) return emit(Op::Var, 0.0, it->second);
      if (auto it = constants_.find(name); it != constants_.end()) return emit(Op::Const, it->second);
      if (name == "pi") return emit(Op::Const, std::numbers::pi);
      if (name == "e") return emit(Op::Const, std::numbers::e);
      s_.fail(at, "unknown name '" + name + "' (not a parameter of the predecessor or its context, nor a constant)");
    }
    s_.fail(p_, std::string("unexpected '") + c + "' in expression");
  }

  // Constant folding of the whole expression when it uses no variables and no random draws.
  static void fold(Expr& e) {
    for (const Instr& in : e.code)
      if (in.op == Op::Var || in.op == Op::Uniform || in.op == Op::Gauss) return;
    Draws none;
    const double v = eval(e, nullptr, none);
    e.code.assign(1, Instr{Op::Const, 0, v});
  }

  const Source& s_;
  std::size_t p_, end_;
  const std::map<std::string, int>& vars_;
  const std::map<std::string, double>& constants_;
  std::vector<Instr>* code_ = nullptr;
  int depth_ = 0, max_depth_ = 0;
};

// --- modules and rules ----------------------------------------------------------------------------------------

bool valid_symbol(char c) {
  const auto u = static_cast<unsigned char>(c);
  return u > 32 && u < 127 && !std::strchr("(),:;", c);
}

struct Pattern {  // a module of a predecessor or context: a symbol and formal parameter slots
  char symbol;
  std::vector<int> slots;
};

struct Template {  // a module of a successor or the axiom
  char symbol;
  std::vector<Expr> args;
};

struct Rule {
  std::vector<Pattern> left;  // in word order
  Pattern pred;
  std::vector<Pattern> right;  // may hold '[' and ']'
  std::optional<Expr> condition;
  Expr weight;
  std::vector<Template> successor;
  int slots = 0;
  bool has_context() const { return !left.empty() || !right.empty(); }
};

std::size_t find_top_level(const std::string& t, std::size_t b, std::size_t e, char c) {
  int depth = 0;
  for (std::size_t i = b; i < e; ++i) {
    if (t[i] == '(') ++depth;
    else if (t[i] == ')') --depth;
    else if (depth == 0 && t[i] == c) return i;
  }
  return std::string::npos;
}

std::size_t skip_space(const std::string& t, std::size_t p, std::size_t e) {
  while (p < e && std::isspace(static_cast<unsigned char>(t[p]))) ++p;
  return p;
}

// The end of a parenthesised group starting at `open` ('('), or fails.
std::size_t close_paren(const Source& s, std::size_t open, std::size_t e) {
  int depth = 0;
  for (std::size_t i = open; i < e; ++i) {
    if (s.text[i] == '(') ++depth;
    else if (s.text[i] == ')' && --depth == 0) return i;
  }
  s.fail(open, "unbalanced '(': no matching ')'");
}

// Predecessor or context modules: symbols with optional (name, name, ...) formal parameters.
std::vector<Pattern> parse_patterns(const Source& s, std::size_t b, std::size_t e, std::map<std::string, int>& vars,
                                    bool allow_brackets) {
  std::vector<Pattern> out;
  int depth = 0;
  for (std::size_t p = skip_space(s.text, b, e); p < e; p = skip_space(s.text, p, e)) {
    const char c = s.text[p];
    if (!valid_symbol(c)) s.fail(p, std::string("'") + c + "' cannot be a module symbol");
    if ((c == '[' || c == ']') && !allow_brackets) s.fail(p, "brackets are allowed in the right context only");
    if (c == '[') ++depth;
    if (c == ']' && --depth < 0) s.fail(p, "']' without '[' in the context");
    Pattern m{c, {}};
    ++p;
    std::size_t q = skip_space(s.text, p, e);
    if (q < e && s.text[q] == '(') {
      const std::size_t close = close_paren(s, q, e);
      std::size_t a = q + 1;
      for (;;) {
        a = skip_space(s.text, a, close);
        const std::size_t start = a;
        if (a >= close || !ident_start(s.text[a])) s.fail(a, "parameter name expected");
        while (a < close && ident_char(s.text[a])) ++a;
        const std::string name = s.text.substr(start, a - start);
        if (vars.count(name)) s.fail(start, "parameter '" + name + "' appears twice in the rule's left side");
        if (static_cast<int>(vars.size()) >= kMaxSlots) s.fail(start, "too many parameters in one rule");
        const int slot = static_cast<int>(vars.size());
        vars[name] = slot;
        m.slots.push_back(slot);
        if (static_cast<int>(m.slots.size()) > kMaxParams) s.fail(start, "more than 16 parameters in a module");
        a = skip_space(s.text, a, close);
        if (a == close) break;
        if (s.text[a] != ',') s.fail(a, "',' or ')' expected after a parameter name");
        ++a;
      }
      p = close + 1;
    }
    out.push_back(std::move(m));
  }
  if (depth != 0) s.fail(e, "'[' without ']' in the context");
  return out;
}

// Successor or axiom modules with expression arguments.
std::vector<Template> parse_templates(const Source& s, std::size_t b, std::size_t e, const std::map<std::string, int>& vars,
                                      const std::map<std::string, double>& constants) {
  std::vector<Template> out;
  for (std::size_t p = skip_space(s.text, b, e); p < e; p = skip_space(s.text, p, e)) {
    const char c = s.text[p];
    if (!valid_symbol(c)) s.fail(p, std::string("'") + c + "' cannot be a module symbol");
    Template m{c, {}};
    ++p;
    if (p < e && s.text[p] == '(') {
      const std::size_t close = close_paren(s, p, e);
      std::size_t a = p + 1;
      for (;;) {
        std::size_t comma = find_top_level(s.text, a, close, ',');
        if (comma == std::string::npos) comma = close;
        if (skip_space(s.text, a, comma) == comma) s.fail(a, "empty parameter");
        m.args.push_back(ExprParser(s, a, comma, vars, constants).parse_all());
        if (static_cast<int>(m.args.size()) > kMaxParams) s.fail(a, "more than 16 parameters in a module");
        if (comma == close) break;
        a = comma + 1;
      }
      p = close + 1;
    }
    out.push_back(std::move(m));
  }
  return out;
}

}  // namespace

struct LSystem::Impl {
  std::vector<Template> axiom;
  std::vector<Rule> rules;
  std::array<std::vector<int>, 256> by_symbol;  // rule indices per predecessor symbol
  std::array<bool, 256> ignored{};
  bool any_context = false;

  ModuleString step(const ModuleString& word, int iteration, std::uint64_t seed, std::size_t max_modules,
                    const std::function<bool()>& should_stop) const;
  bool match_left(const Rule& r, const ModuleString& w, const std::vector<std::int32_t>& match, std::size_t i,
                  double* vars) const;
  bool match_right(const Rule& r, std::size_t p, const ModuleString& w, const std::vector<std::int32_t>& match,
                   std::size_t j, double* vars) const;
};

LSystem::LSystem(const std::string& axiom, const std::string& rules, const std::string& ignore)
    : impl_(std::make_unique<Impl>()) {
  for (char c : ignore)
    if (!std::isspace(static_cast<unsigned char>(c))) impl_->ignored[static_cast<unsigned char>(c)] = true;
  std::map<std::string, double> constants;

  const Source src("rules", rules, true);
  const std::string& t = src.text;
  std::size_t b = 0;
  while (b <= t.size()) {
    std::size_t e = b;
    while (e < t.size() && t[e] != '\n' && t[e] != ';') ++e;
    const std::size_t first = skip_space(t, b, e);
    const bool comment = t.compare(first, 2, "//") == 0 && first + 2 <= e;
    if (first < e && !comment) {
      const std::size_t arrow = t.find("->", first);
      if (t.compare(first, 4, "let ") == 0 && (arrow == std::string::npos || arrow >= e)) {
        // let name = expr
        std::size_t p = skip_space(t, first + 4, e);
        const std::size_t start = p;
        if (p >= e || !ident_start(t[p])) src.fail(p, "constant name expected after 'let'");
        while (p < e && ident_char(t[p])) ++p;
        const std::string name = t.substr(start, p - start);
        p = skip_space(t, p, e);
        if (p >= e || t[p] != '=') src.fail(p, "'=' expected after the constant's name");
        const std::map<std::string, int> none;
        const Expr v = ExprParser(src, p + 1, e, none, constants).parse_all();
        if (!v.constant()) src.fail(p + 1, "a constant cannot use random draws");
        constants[name] = v.code[0].value;
      } else {
        if (arrow == std::string::npos || arrow >= e) src.fail(first, "'->' expected: a rule reads 'predecessor -> successor'");
        Rule r;
        std::map<std::string, int> vars;
        // Left side: [left <] pred [> right] [: condition]
        std::size_t lhs_end = arrow;
        const std::size_t colon = find_top_level(t, first, arrow, ':');
        const std::size_t ctx_end = colon == std::string::npos ? arrow : colon;
        std::size_t pred_b = first, pred_e = ctx_end;
        const std::size_t lt = find_top_level(t, first, ctx_end, '<');
        if (lt != std::string::npos) {
          r.left = parse_patterns(src, first, lt, vars, false);
          if (r.left.empty()) src.fail(lt, "left context expected before '<'");
          pred_b = lt + 1;
        }
        const std::size_t gt = find_top_level(t, pred_b, ctx_end, '>');
        if (gt != std::string::npos) pred_e = gt;
        auto pred = parse_patterns(src, pred_b, pred_e, vars, false);
        if (pred.size() != 1)
          src.fail(skip_space(t, pred_b, pred_e), pred.empty() ? "predecessor expected" : "the predecessor is a single module (use '<' and '>' for contexts)");
        r.pred = std::move(pred[0]);
        if (gt != std::string::npos) {
          r.right = parse_patterns(src, gt + 1, ctx_end, vars, true);
          if (r.right.empty()) src.fail(gt, "right context expected after '>'");
        }
        const std::map<std::string, double>& consts = constants;
        if (colon != std::string::npos) {
          if (skip_space(t, colon + 1, lhs_end) == lhs_end) src.fail(colon + 1, "condition expected after ':'");
          r.condition = ExprParser(src, colon + 1, lhs_end, vars, consts).parse_all();
        }
        // Right side: successor [: weight]
        const std::size_t succ_b = arrow + 2;
        const std::size_t wcolon = find_top_level(t, succ_b, e, ':');
        const std::size_t succ_e = wcolon == std::string::npos ? e : wcolon;
        r.successor = parse_templates(src, succ_b, succ_e, vars, consts);
        int depth = 0;
        for (std::size_t k = 0; k < r.successor.size(); ++k) {
          if (r.successor[k].symbol == '[') ++depth;
          if (r.successor[k].symbol == ']' && --depth < 0) src.fail(succ_b, "']' without '[' in the successor");
        }
        if (depth != 0) src.fail(succ_b, "'[' without ']' in the successor");
        if (wcolon != std::string::npos) {
          if (skip_space(t, wcolon + 1, e) == e) src.fail(wcolon + 1, "weight expected after ':'");
          r.weight = ExprParser(src, wcolon + 1, e, vars, consts).parse_all();
          if (r.weight.constant() && !(r.weight.code[0].value >= 0.0)) src.fail(wcolon + 1, "a weight must be >= 0");
        } else {
          r.weight.code.assign(1, Instr{Op::Const, 0, 1.0});
        }
        r.slots = static_cast<int>(vars.size());
        if (r.pred.symbol == '[' || r.pred.symbol == ']') src.fail(first, "brackets cannot be rewritten");
        impl_->any_context = impl_->any_context || r.has_context();
        impl_->by_symbol[static_cast<unsigned char>(r.pred.symbol)].push_back(static_cast<int>(impl_->rules.size()));
        impl_->rules.push_back(std::move(r));
      }
    }
    if (e >= t.size()) break;
    b = e + 1;
  }

  const Source ax("axiom", axiom, false);
  const std::map<std::string, int> none;
  impl_->axiom = parse_templates(ax, 0, ax.text.size(), none, constants);
  if (impl_->axiom.empty()) ax.fail(0, "the axiom is empty");
  int depth = 0;
  for (const auto& m : impl_->axiom) {
    if (m.symbol == '[') ++depth;
    if (m.symbol == ']' && --depth < 0) ax.fail(0, "']' without '[' in the axiom");
  }
  if (depth != 0) ax.fail(ax.text.size(), "'[' without ']' in the axiom");
}

LSystem::~LSystem() = default;
LSystem::LSystem(LSystem&&) noexcept = default;
LSystem& LSystem::operator=(LSystem&&) noexcept = default;
std::size_t LSystem::rule_count() const { return impl_->rules.size(); }

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
      if (c == ']') j = match[static_cast<std::size_t>(j)] - 1;  // a sibling branch: skip it whole
      else if (c == '[' || ignored[static_cast<unsigned char>(c)]) --j;  // '[': step out to the parent
      else break;
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
        if (c == '[') j = static_cast<std::size_t>(match[j]) + 1;
        else if (c == ']') {
          ++j;
          break;
        } else ++j;
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
      if (j < n && w.symbols[j] == '[') j = static_cast<std::size_t>(match[j]) + 1;
      else break;
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
      if (w.symbols[k] == '[') stack.push_back(static_cast<std::int32_t>(k));
      else if (w.symbols[k] == ']') {
        if (stack.empty()) match[k] = -1;
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
