#pragma once
// The time written into image headers (TIFF DateTime, EXR capDate): identical graphs must give identical
// files, so it is never the time of writing. With SOURCE_DATE_EPOCH set (https://reproducible-builds.org/
// specs/source-date-epoch/) it is that time, "YYYY:MM:DD HH:MM:SS" in UTC; otherwise empty, which leaves
// the field out of TIFF files and empty in EXR files.
#include <string>

namespace orogen {

std::string file_timestamp();

}  // namespace orogen
