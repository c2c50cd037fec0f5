#pragma once
// The phase tags of the across-tiles algorithms run in phases (flow, rivers, drainage metrics): every message and
// answer starts with its phase's byte, so each tile and the solve know where the run stands. `Phase` is an enum over
// std::uint8_t whose last value is Done. `what` names the bytes for bytes::take; `who` starts the error messages.
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "graph/tile_bytes.h"

namespace orogen::hydrology {

template <class Phase>
std::string tagged(Phase phase, std::string payload) {
  payload.insert(payload.begin(), static_cast<char>(phase));
  return payload;
}

// The phase a message or answer is tagged with; `bytes` keeps the rest.
template <class Phase>
Phase take_phase(std::string_view& bytes, const char* what, const std::string& who) {
  const auto p = bytes::take<std::uint8_t>(bytes, what);
  if (p > static_cast<std::uint8_t>(Phase::Done)) throw std::invalid_argument(who + ": unknown phase");
  return static_cast<Phase>(p);
}

template <class Phase>
struct UntaggedMessages {
  Phase phase = Phase::Done;
  std::vector<std::string_view> views;  // into the tagged messages, past their tags
};

// The tiles' messages without their tags, and their phase (Done if none): every tile must be in the same one.
template <class Phase>
UntaggedMessages<Phase> untag_messages(const std::vector<std::string>& tagged_messages, const char* what,
                                       const std::string& who) {
  UntaggedMessages<Phase> out;
  out.views.reserve(tagged_messages.size());
  for (const std::string& m : tagged_messages) {
    std::string_view v(m);
    const Phase p = take_phase<Phase>(v, what, who);
    if (!out.views.empty() && p != out.phase) throw std::invalid_argument(who + ": tiles in different phases");
    out.phase = p;
    out.views.push_back(v);
  }
  return out;
}

// Views of whole messages, for the solves that take views (std::span<const std::string_view>).
inline std::vector<std::string_view> message_views(const std::vector<std::string>& messages) {
  return {messages.begin(), messages.end()};
}

inline void expect_end(std::string_view in, const std::string& who) {
  if (!in.empty()) throw std::invalid_argument(who + ": trailing bytes");
}

}  // namespace orogen::hydrology
