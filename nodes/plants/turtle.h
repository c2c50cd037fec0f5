#pragma once
// A 3D turtle interpreting an L-system word (Prusinkiewicz & Lindenmayer 1990, The Algorithmic Beauty of
// Plants, ch. 1.5 and 2.2) into a branching skeleton (Curves) and leaf placements (Points).
//
// Symbols (parameters optional; angles in degrees, lengths in metres):
//   F(l)  move forward l (default step) drawing a branch segment     f(l)  move without drawing
//   +(a)  turn left about the up axis       -(a)  turn right          |     turn around (180 deg)
//   &(a)  pitch down about the left axis    ^(a)  pitch up
//   \(a)  roll left about the heading       /(a)  roll right          $     roll until left is horizontal
//   [ ]   push / pop the turtle state       #(r,g,b) set the color (0..255 sRGB)
//   <(k)  thicken: width * k (default 1/width_factor)   >(k)  narrow: width * k (default width_factor)
//   !(w)  set the width to w metres (no parameter: like >)        L(s,r,g,b) a leaf of size s metres (color optional,
//   0..255)
// Other symbols are ignored. The frame (heading H, left L, up U = H x L) starts with H = +z, L = -x,
// U = -y, so a word drawn in the turtle's plane faces a viewer looking along +y. It is re-orthonormalised
// after every rotation (Gram-Schmidt), so it stays orthonormal over any number of turns. Tropism (ABOP
// eq. 2.5): after each F the heading bends towards T by the angle e |H x T|.
#include <cstdint>
#include <functional>

#include <glm/vec3.hpp>

#include "graph/curves.h"
#include "graph/module_string.h"
#include "graph/points.h"

namespace orogen::plants {

struct TurtleOptions {
  double step = 1.0;                       // metres, F and f without a parameter
  double angle = 25.0;                     // degrees, rotations without a parameter
  double width = 0.1;                      // metres, initial branch width (diameter)
  double width_factor = 0.7;               // > multiplies, < divides the width by this without a parameter
  glm::dvec3 tropism{0.0, 0.0, -1.0};      // direction T (gravity: down)
  double tropism_strength = 0.0;           // e, radians of bending per unit |H x T| per F
  glm::dvec3 color{0.35, 0.22, 0.12};      // linear RGB initial color
  double leaf_size = 0.2;                  // metres, L without a parameter
  glm::dvec3 leaf_color{0.1, 0.35, 0.05};  // linear RGB, L without color parameters
  std::function<bool()> should_stop;
};

// The turtle's state; exposed for tests.
struct TurtleFrame {
  glm::dvec3 position{0.0};
  glm::dvec3 heading{0.0, 0.0, 1.0}, left{-1.0, 0.0, 0.0}, up{0.0, -1.0, 0.0};
};

struct TurtleResult {
  Curves skeleton;  // one curve per branch (a run of F); parent = the branch it starts from; per-point
                    // width (m) and attributes "r", "g", "b" (linear color) and "depth" (bracket depth)
  Points leaves;    // position, rotation (turtle frame: local x = heading, y = left, z = up), scale =
                    // leaf size (m), attributes "r", "g", "b" and "branch" (index of the curve it grows on, -1:
                    // none)
  TurtleFrame final_frame;
};

TurtleResult interpret(const ModuleString& word, const TurtleOptions& options);

// Rotates the frame by `degrees` about its up (0), left (1) or heading (2) axis and re-orthonormalises.
void rotate(TurtleFrame& f, int axis, double degrees);

}  // namespace orogen::plants
