#pragma once
// The inspector's widget for table parameters: one line per row with a typed cell per column (text field,
// number drag within the column's range, range drag pair, sRGB color picker, enum combo), buttons to move a
// row up or down or delete it, and one to add a row. Structural edits report `changed` and `finished`
// together (one undo step); drags report `changed` every frame and `finished` when released.
#include "editor/ui/curve_editor.h"
#include "graph/table_value.h"

namespace orogen::editor {

WidgetEdit table_editor(const char* id, const TableSchema& schema, TableValue& table, float width);

}  // namespace orogen::editor
