#pragma once
// What the preview panels show: the output of the previewed node, plus (for points, curves, polygon maps,
// meshes and water depth) the heightfield it was built on as a backdrop, plus an optional image to drape
// in 3D.
#include <optional>
#include <string>

#include "editor/model/scene_preview.h"
#include "graph/node_type.h"
#include "graph/port_value.h"

namespace orogen::editor {

struct PreviewContent {
  std::string node;                    // the previewed node ("" if none)
  std::string port;                    // its shown output
  PortValue value;                     // monostate while not (yet) evaluated
  OutputKind kind = OutputKind::Auto;  // of a heightfield value: chooses the colour map (and water in 3D)
  std::string backdrop_node;           // the heightfield under points / curves / meshes
  HeightfieldPtr backdrop;
  ImagePtr drape;            // 3D: colour image draped over the terrain
  std::uint64_t serial = 0;  // the evaluation result it comes from; changes when the data do
  bool stale = false;        // a newer evaluation is running
  std::string error;         // why there is no value (the node failed, or an upstream node did)
  // A scene writer (WriteScene) is previewed as the scene it writes: `value` holds its points, `backdrop`
  // the ground they were placed on, and 3D draws the terrain mesh and the class meshes instanced.
  std::optional<ScenePreview> scene;
};

}  // namespace orogen::editor
