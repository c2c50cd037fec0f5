#pragma once
// Flat plant sprites: a 2D turtle (Prusinkiewicz & Lindenmayer 1990, The Algorithmic Beauty of Plants,
// ch. 1.3-1.6: bracketed L-systems drawn in a plane) interprets an L-system word in the vertical x-z plane and
// every drawn segment becomes a ribbon quad of the branch's width in that plane; optionally the drawing is
// repeated in the y-z plane (two crossed planes, the classic billboard cross: Reeves & Blau 1985 style
// vegetation impostors, as used by SpeedTree-era games) so the plant reads from every side.
//
// Symbols (parameters optional; angles in degrees, lengths in metres):
//   F(l)  draw forward l (default step)        f(l)  move forward without drawing
//   +(a)  turn left (heading towards -x)         -(a)  turn right          |  turn around (180 deg)
//   [ ]   push / pop the turtle state (a push starts a branch one level deeper: width * taper)
//   !(w)  set the width to w metres              <leaf symbol>(s) a leaf of size s (default leaf_size)
// Other symbols (3D rotations, colors, X, A ...) are ignored. The turtle starts at the origin heading up
// (+z); the finished mesh is lifted so its lowest point is at z = 0 (the plant stands on the ground at its
// root, not centred).
#include <cstddef>
#include <functional>

#include <glm/vec4.hpp>

#include "graph/mesh.h"
#include "graph/module_string.h"

namespace orogen::plants {

struct PlantSpriteOptions {
  double step = 0.1;                                // metres, F and f without a parameter
  double angle = 25.0;                              // degrees, + and - without a parameter
  double width = 0.05;                              // metres, ribbon width of the trunk (branch level 0)
  double taper = 0.7;                               // width factor per branch level ([), 0..1
  bool crossed = true;                              // a second copy of the drawing in the y-z plane
  char leaf_symbol = 'L';                           // '\0': no leaves
  double leaf_size = 0.15;                          // metres, leaf length without a parameter (its width is half of it)
  glm::vec4 color{0.30f, 0.20f, 0.10f, 1.0f};       // linear RGBA of the stems
  glm::vec4 leaf_color{0.10f, 0.35f, 0.05f, 1.0f};  // linear RGBA of the leaves
  std::size_t max_triangles = 2000000;              // budget; over it: std::invalid_argument
  std::function<bool()> should_stop;
};

struct PlantSpriteStats {
  std::size_t segments = 0;  // drawn F
  std::size_t leaves = 0;
  double height = 0.0;  // metres, top of the mesh above its lowest point
};

// Each segment and each leaf is one quad (4 vertices, 2 triangles) per plane, with the plane's normal
// (-y for the x-z plane, +x for the y-z plane). Throws std::invalid_argument over the triangle budget.
Mesh plant_sprite(const ModuleString& word, const PlantSpriteOptions& options, PlantSpriteStats* stats = nullptr);

}  // namespace orogen::plants
