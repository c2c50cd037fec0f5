#pragma once
// The metre mapping of a 16-bit height file, beside it as JSON (`height.png` -> `height.png.json`): a RAW file
// has no metadata at all, and engines and DCC tools ignore PNG's, so without it a range 'auto' file loses its
// metres. Holds the heights stored as 0 and 65535, the cell size, the south-west sample's position, and the
// scale to type into Unreal Engine's landscape import (X/Y: cm per sample; Z: 100 spans 512 m over 0..65535).
#include <string>

#include "graph/heightfield.h"
#include "nodes/io/heightfield_file.h"

namespace orogen {

std::string height_sidecar_json(const Domain& domain, HeightFormat format, const HeightRange& range,
                                const std::string& image_file_name);
inline std::string height_sidecar_json(const Heightfield& h, HeightFormat format, const HeightRange& range,
                                       const std::string& image_file_name) {
  return height_sidecar_json(h.domain, format, range, image_file_name);
}

}  // namespace orogen
