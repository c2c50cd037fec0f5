#pragma once
// Plain values as bytes and back, for the messages tiles exchange in a tile-graph run (graph/tile_graph.h). Ranks
// of one job run the same build on the same kind of machine, so values travel in the machine's own layout.
#include <cstring>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace orogen::bytes {

template <class T>
void put(std::string& out, const T& v) {
  out.append(reinterpret_cast<const char*>(&v), sizeof v);
}

// Takes one value from the front of `in`; throws std::invalid_argument naming `what` if `in` is too short.
template <class T>
T take(std::string_view& in, const char* what) {
  if (in.size() < sizeof(T)) throw std::invalid_argument(std::string(what) + ": truncated bytes");
  T v;
  std::memcpy(&v, in.data(), sizeof v);
  in.remove_prefix(sizeof v);
  return v;
}

template <class T>
void put_vector(std::string& out, const std::vector<T>& v) {
  put(out, static_cast<std::uint64_t>(v.size()));
  if (!v.empty()) out.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
}

template <class T>
std::vector<T> take_vector(std::string_view& in, const char* what) {
  const auto n = take<std::uint64_t>(in, what);
  if (n > in.size() / sizeof(T)) throw std::invalid_argument(std::string(what) + ": truncated bytes");
  std::vector<T> v(static_cast<std::size_t>(n));
  if (n > 0) std::memcpy(v.data(), in.data(), v.size() * sizeof(T));  // an empty vector's data() may be null
  in.remove_prefix(v.size() * sizeof(T));
  return v;
}

}  // namespace orogen::bytes
