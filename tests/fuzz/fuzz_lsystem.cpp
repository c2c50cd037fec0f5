// libFuzzer target: the L-system grammar a user types into LSystem's `axiom`, `rules` and `ignore`
// parameters (nodes/plants/lsystem.h), then the derived word through the turtle. Input layout: the first byte
// picks the iteration count (0-4) and seed; the rest is "axiom\x01rules\x01ignore" (missing parts empty).
// A bad grammar must fail with LSystemError (a position in the text), a runaway one at the module bound,
// never crash, hang or read out of bounds. Seed corpus (tests/fuzz/lsystem_seeds): the grammars of graphs/plants.json.
#include <cstddef>
#include <cstdint>
#include <string>

#include "nodes/plants/lsystem.h"
#include "nodes/plants/turtle.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const std::string text(reinterpret_cast<const char*>(data + 1), size - 1);
  std::string parts[3];
  for (std::size_t start = 0, k = 0; k < 3; ++k) {
    const std::size_t end = k < 2 ? text.find('\x01', start) : std::string::npos;
    parts[k] = text.substr(start, end == std::string::npos ? std::string::npos : end - start);
    if (end == std::string::npos) break;
    start = end + 1;
  }
  try {
    const orogen::plants::LSystem system(parts[0], parts[1], parts[2]);
    orogen::plants::DeriveOptions options;
    options.iterations = data[0] % 5;
    options.seed = data[0] >> 3;
    options.max_modules = 20000;  // small: each run stays fast, and the bound itself is exercised
    const orogen::ModuleString word = system.derive(options);
    orogen::plants::TurtleOptions turtle;
    turtle.tropism_strength = 0.2;
    (void)orogen::plants::interpret(word, turtle);
  } catch (const orogen::plants::LSystemError&) {
    // The expected refusal of a bad or runaway grammar.
  }
  return 0;
}
