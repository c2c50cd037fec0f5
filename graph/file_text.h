#pragma once
// Text a node writes into a file (a texture name in a material library, ...) must not change the file's
// structure: one printable line, no control characters (a newline would start a new directive).
#include <string>

namespace orogen {

// Empty if `text` may be written into a line of a text file, else why not (names the byte).
std::string check_file_text(const std::string& text);

}  // namespace orogen
