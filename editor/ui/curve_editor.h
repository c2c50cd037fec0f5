#pragma once
// Inspector widgets for curve and gradient parameters.
//
// Both edit a working copy and report `changed` every frame the value moves and `finished` when the mouse
// gesture ends, so the inspector can merge a drag into one undo step.
#include <imgui.h>

#include "graph/param_value.h"

namespace orogen::editor {

struct WidgetEdit {
  bool changed = false;
  bool finished = false;
};

// A monotone-cubic curve: drag points (x stays between its neighbours), double-click to add a point,
// right-click a point to remove it (at least two stay).
WidgetEdit curve_editor(const char* id, CurveValue& curve, float width);

// A colour gradient: drag stops along the bar, click one to edit its colour, double-click the bar to add a
// stop, right-click a stop to remove it (at least one stays).
WidgetEdit gradient_editor(const char* id, GradientValue& gradient, float width);

}  // namespace orogen::editor
