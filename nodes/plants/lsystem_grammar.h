#pragma once
// The parsed form of an L-system (lsystem.h): predecessor and context patterns with formal parameter slots,
// successor templates with compiled expressions, and the parser that builds them from the text.
#include <optional>
#include <string>
#include <vector>

#include "nodes/plants/lsystem_eval.h"

namespace orogen::plants::lsys {

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

struct Grammar {
  std::vector<Template> axiom;
  std::vector<Rule> rules;  // in the order of the text
};

// Parses the rules (one per line or separated by ';', with 'let' constants and '//' comments), then the axiom.
// Throws LSystemError with the position of the first error.
Grammar parse_grammar(const std::string& axiom, const std::string& rules);

}  // namespace orogen::plants::lsys
