#pragma once
// The L-system's expression evaluator (lsystem.h): compiled expressions as postfix code over a small stack,
// and the counter-based random draws of uniform() and gauss(). Internal to the L-system's parser and
// rewriter; inline so that the rewriter's inner loop keeps evaluating without a call.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <numbers>
#include <vector>

#include "nodes/common/hash.h"

namespace orogen::plants::lsys {

inline constexpr int kMaxParams = 16;  // per module
inline constexpr int kMaxSlots = 64;   // formal parameters per rule

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

// --- expressions ------------------------------------------------------------------------------------------------

enum class Op : std::uint8_t {
  Const,
  Var,
  Add,
  Sub,
  Mul,
  Div,
  Pow,
  Neg,
  Not,
  Lt,
  Le,
  Gt,
  Ge,
  Eq,
  Ne,
  And,
  Or,
  Sin,
  Cos,
  Tan,
  Asin,
  Acos,
  Atan,
  Atan2,
  Sqrt,
  Abs,
  Min,
  Max,
  Floor,
  Ceil,
  Exp,
  Log,
  Clamp,
  Uniform,
  Gauss
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

inline constexpr double kDeg = std::numbers::pi / 180.0;

// The stack machine; eval() below is the entry.
inline double run(const Expr& e, const double* vars, Draws& draws) {
  double stack[64];
  int sp = 0;
  for (const Instr& in : e.code) {
    switch (in.op) {
      case Op::Const:
        stack[sp++] = in.value;
        break;
      case Op::Var:
        stack[sp++] = vars[in.slot];
        break;
#define BIN(OP, EXPR)               \
  case Op::OP: {                    \
    const double b = stack[--sp];   \
    const double a = stack[sp - 1]; \
    stack[sp - 1] = (EXPR);         \
    break;                          \
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
#define UN(OP, EXPR)                \
  case Op::OP: {                    \
    const double a = stack[sp - 1]; \
    stack[sp - 1] = (EXPR);         \
    break;                          \
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

// A constant or a parameter passed on, the commonest arguments, without the stack machine (and small enough to
// inline where the rewriter evaluates).
inline double eval(const Expr& e, const double* vars, Draws& draws) {
  if (e.code.size() == 1) {
    const Instr& in = e.code[0];
    if (in.op == Op::Const) return in.value;
    if (in.op == Op::Var) return vars[in.slot];
  }
  return run(e, vars, draws);
}

}  // namespace orogen::plants::lsys
