#include "graph/file_text.h"

#include <cstdio>

namespace orogen {

std::string check_file_text(const std::string& text) {
  for (std::size_t i = 0; i < text.size(); ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c < 0x20 || c == 0x7f) {
      char code[8];
      std::snprintf(code, sizeof code, "0x%02x", c);
      return std::string("contains the control character ") + code + " at byte " + std::to_string(i) +
             "; text written into a file must be one printable line";
    }
  }
  return {};
}

}  // namespace orogen
