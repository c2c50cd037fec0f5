#pragma once
// Edits made to the example graphs after their fixtures (tests/fixtures/v1..v5) were taken, which no migration
// performs: the tests that compare a migrated fixture with today's example apply them to
// the fixture's text first, so everything else must still match exactly.
#include <map>
#include <string>

namespace orogen::test {

struct LaterTextEdit {
  std::string from, to;
  int fixtures;  // how many fixtures contain `from`, so a stale entry fails instead of passing silently
};

inline const LaterTextEdit kLaterTextEdits[] = {
    // The L-system rule comment credited SeamScape to "Chalmers et al."; its authors are S. Ekman et al.
    {"(Chalmers et al. 2016, Appendix A", "(S. Ekman et al. 2016, a Chalmers bachelor thesis, Appendix A", 11},
    // Format 7: the examples' OBJ writers take the new default, y-up (auto), where a migrated file keeps Z.
    {"\"params\": { \"path\": \"foundation/terrain.obj\" }",
     "\"params\": { \"path\": \"foundation/terrain.obj\", \"up_axis\": \"auto\" }", 5},
    {"\"path\": \"textured_terrain/terrain.obj\",",
     "\"path\": \"textured_terrain/terrain.obj\",\n        \"up_axis\": \"auto\",", 3},
    {"\"path\": \"terrain/terrain.obj\", \"texture\"",
     "\"path\": \"terrain/terrain.obj\", \"up_axis\": \"auto\", \"texture\"", 4},
    {"\"path\": \"seamscape/terrain.obj\", \"texture\"",
     "\"path\": \"seamscape/terrain.obj\", \"up_axis\": \"auto\", \"texture\"", 2},
    {"\"path\": \"game_world/plant_4_19.obj\" }", "\"path\": \"game_world/plant_4_19.obj\", \"up_axis\": \"auto\" }",
     2},
    {"\"path\": \"game_world/plant_4_20.obj\" }", "\"path\": \"game_world/plant_4_20.obj\", \"up_axis\": \"auto\" }",
     2},
    // Distributed builds: a blur of the lakes filled across tiles, so its halo comes from the neighboring tiles.
    {"\"path\": \"distributed_hydrology/lake_depth.tif\"\n      }\n    }\n",
     "\"path\": \"distributed_hydrology/lake_depth.tif\"\n      }\n    },\n    {\n      \"id\": \"filled_smooth\",\n"
     "      \"type\": \"Blur\",\n      \"inputs\": {\n        \"in\": \"filled_flat.out\"\n      },\n      \"params\": "
     "{\n"
     "        \"sigma\": 100\n      }\n    },\n    {\n      \"id\": \"save_filled_smooth\",\n      \"type\": "
     "\"WriteHeightfield\",\n      \"inputs\": {\n        \"in\": \"filled_smooth.out\"\n      },\n      \"params\": "
     "{\n"
     "        \"path\": \"distributed_hydrology/filled_smooth.tif\"\n      }\n    }\n",
     1},
};

// `text` with every later edit applied; counts in `applied[from]` the texts each edit changed.
inline std::string with_later_text_edits(std::string text, std::map<std::string, int>& applied) {
  for (const auto& edit : kLaterTextEdits) {
    bool found = false;
    for (auto at = text.find(edit.from); at != std::string::npos; at = text.find(edit.from, at + edit.to.size())) {
      text.replace(at, edit.from.size(), edit.to);
      found = true;
    }
    applied[edit.from] += found ? 1 : 0;
  }
  return text;
}

}  // namespace orogen::test
