// The L-system parser (lsystem.h): rules, 'let' constants and the axiom into a Grammar, with positions in
// errors.
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstring>
#include <map>
#include <string>
#include <string_view>
#include <utility>

#include "nodes/plants/lsystem.h"
#include "nodes/plants/lsystem_grammar.h"

namespace orogen::plants::lsys {
namespace {

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
      static constexpr Sub subs[] = {{"\u2192", "->"}, {"\u2212", "-"},  {"\u00d7", "*"},
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

struct Function {
  std::string_view name;
  Op op;
  int arity;
};
constexpr Function kFunctions[] = {
    {"sin", Op::Sin, 1},     {"cos", Op::Cos, 1},         {"tan", Op::Tan, 1},     {"asin", Op::Asin, 1},
    {"acos", Op::Acos, 1},   {"atan", Op::Atan, 1},       {"atan2", Op::Atan2, 2}, {"sqrt", Op::Sqrt, 1},
    {"abs", Op::Abs, 1},     {"min", Op::Min, 2},         {"max", Op::Max, 2},     {"floor", Op::Floor, 1},
    {"ceil", Op::Ceil, 1},   {"exp", Op::Exp, 1},         {"log", Op::Log, 1},     {"pow", Op::Pow, 2},
    {"clamp", Op::Clamp, 3}, {"uniform", Op::Uniform, 2}, {"U", Op::Uniform, 2},   {"gauss", Op::Gauss, 2},
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
      if (accept("<="))
        op = Op::Le;
      else if (accept(">="))
        op = Op::Ge;
      else if (accept("=="))
        op = Op::Eq;
      else if (accept("!="))
        op = Op::Ne;
      else if (accept("<"))
        op = Op::Lt;
      else if (accept(">"))
        op = Op::Gt;
      else
        return;
      parse_add();
      emit(op), pop(1);
    }
  }
  void parse_add() {
    parse_mul();
    for (;;) {
      if (accept("+"))
        parse_mul(), emit(Op::Add), pop(1);
      else if (accept("-"))
        parse_mul(), emit(Op::Sub), pop(1);
      else
        return;
    }
  }
  void parse_mul() {
    parse_unary();
    for (;;) {
      if (accept("*"))
        parse_unary(), emit(Op::Mul), pop(1);
      else if (accept("/"))
        parse_unary(), emit(Op::Div), pop(1);
      else
        return;
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
          if (k > 0 && !accept(","))
            s_.fail(p_, "',' expected: " + name + " takes " + std::to_string(f->arity) + " arguments");
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

std::size_t find_top_level(const std::string& t, std::size_t b, std::size_t e, char c) {
  int depth = 0;
  for (std::size_t i = b; i < e; ++i) {
    if (t[i] == '(')
      ++depth;
    else if (t[i] == ')')
      --depth;
    else if (depth == 0 && t[i] == c)
      return i;
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
    if (s.text[i] == '(')
      ++depth;
    else if (s.text[i] == ')' && --depth == 0)
      return i;
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
std::vector<Template> parse_templates(const Source& s, std::size_t b, std::size_t e,
                                      const std::map<std::string, int>& vars,
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

Grammar parse_grammar(const std::string& axiom, const std::string& rules) {
  Grammar g;
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
        if (arrow == std::string::npos || arrow >= e)
          src.fail(first, "'->' expected: a rule reads 'predecessor -> successor'");
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
          src.fail(skip_space(t, pred_b, pred_e),
                   pred.empty() ? "predecessor expected"
                                : "the predecessor is a single module (use '<' and '>' for contexts)");
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
        g.rules.push_back(std::move(r));
      }
    }
    if (e >= t.size()) break;
    b = e + 1;
  }

  const Source ax("axiom", axiom, false);
  const std::map<std::string, int> none;
  g.axiom = parse_templates(ax, 0, ax.text.size(), none, constants);
  if (g.axiom.empty()) ax.fail(0, "the axiom is empty");
  int depth = 0;
  for (const auto& m : g.axiom) {
    if (m.symbol == '[') ++depth;
    if (m.symbol == ']' && --depth < 0) ax.fail(0, "']' without '[' in the axiom");
  }
  if (depth != 0) ax.fail(ax.text.size(), "'[' without ']' in the axiom");
  return g;
}

}  // namespace orogen::plants::lsys
