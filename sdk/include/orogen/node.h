#pragma once
// The Orogen node SDK: everything a node library needs to declare and implement node types.
//
//   #include <orogen/node.h>
//   using namespace orogen;
//   OROGEN_NODE(Canyon) {
//     b.category("field").description("...");
//     b.reach_pointwise();
//     b.input("in", PortType::Heightfield).description("Heights, metres");
//     b.output("out", PortType::Heightfield).description("Heights, metres");
//     b.param_float("step", 20.0).range(0.01, 1e4).unit(Unit::Metre).description("Height of one terrace");
//     b.execute([](ExecContext& ctx) { ... ctx.set_output("out", result); });
//   }
//
// Build it with find_package(Orogen) and orogen_add_node_library(my_nodes my_node.cpp); test it with
// <orogen/testing.h>. See docs/plugins.md. The public headers are those this one includes (and what they
// include): the value types, the declaration builder (NodeBuilder, OROGEN_NODE), ExecContext and run_node.
#include "evaluator/run_node.h"
#include "graph/curves.h"
#include "graph/domain.h"
#include "graph/exec_context.h"
#include "graph/heightfield.h"
#include "graph/image.h"
#include "graph/node_type.h"
#include "graph/points.h"
#include "graph/registry.h"
#include "orogen/version.h"
