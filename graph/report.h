#pragma once
// A small structured result that is not a field: figures a node measures (drainage metrics, statistics).
// Held as one JSON object in text form so the model needs no JSON library; `orogen eval --stats` embeds it
// under "reports" and the editor can show it as text.
#include <cstddef>
#include <memory>
#include <string>

namespace orogen {

struct Report {
  std::string json = "{}";  // a JSON object

  std::size_t byte_size() const { return json.size() + sizeof(*this); }
};

using ReportPtr = std::shared_ptr<const Report>;

}  // namespace orogen
