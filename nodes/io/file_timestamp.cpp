#include "nodes/io/file_timestamp.h"

#include <charconv>
#include <cstdlib>
#include <cstring>
#include <ctime>

namespace orogen {

std::string file_timestamp() {
  const char* epoch = std::getenv("SOURCE_DATE_EPOCH");
  if (!epoch || !*epoch) return {};
  long long seconds = 0;
  const auto [end, ec] = std::from_chars(epoch, epoch + std::strlen(epoch), seconds);
  if (ec != std::errc() || *end != '\0' || seconds < 0) return {};  // malformed: as if unset
  const std::time_t t = static_cast<std::time_t>(seconds);
  std::tm utc{};
  if (!gmtime_r(&t, &utc)) return {};
  char text[32];
  std::strftime(text, sizeof text, "%Y:%m:%d %H:%M:%S", &utc);
  return text;
}

}  // namespace orogen
