#pragma once
// Binary serialization of every PortValue type, for the persistent cache.
//
// The encoding is little-endian with explicit sizes; every count is checked against the bytes left before
// anything is allocated, and every decoded value is checked for consistency, so a damaged or foreign byte
// stream raises SerializationError instead of producing a wrong value or a huge allocation. It is a cache
// format, not an interchange format: bump kValueFormatVersion whenever the encoding changes.
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "graph/port_value.h"

namespace orogen {

inline constexpr std::uint32_t kValueFormatVersion =
    5;  // 2: ModuleString; optional mesh texcoords. 3: Scene. 4: Image.color. 5: floats by byte plane

struct SerializationError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Appends little-endian primitives to a byte string.
class ByteWriter {
 public:
  ByteWriter() = default;
  // Writes into `reuse`, emptied first: its capacity is kept (no reallocation, no fresh pages to fault in).
  explicit ByteWriter(std::string reuse) : buffer_(std::move(reuse)) { buffer_.clear(); }
  void u8(std::uint8_t v) { buffer_.push_back(static_cast<char>(v)); }
  void u32(std::uint32_t v);
  void u64(std::uint64_t v);
  void i32(std::int32_t v) { u32(static_cast<std::uint32_t>(v)); }
  void i64(std::int64_t v) { u64(static_cast<std::uint64_t>(v)); }
  void f32(float v);
  void f64(double v);
  void str(std::string_view s);
  void raw(const void* data, std::size_t n);
  // A count followed by the elements: ints as they lie, floats as four byte planes (lowest bytes first).
  void floats(const std::vector<float>& v);
  void ints(const std::vector<int>& v);

  const std::string& buffer() const { return buffer_; }
  std::string take() { return std::move(buffer_); }

 private:
  std::string buffer_;
};

// Reads what ByteWriter wrote; throws SerializationError on running past the end.
class ByteReader {
 public:
  explicit ByteReader(std::string_view bytes) : bytes_(bytes) {}
  std::uint8_t u8();
  std::uint32_t u32();
  std::uint64_t u64();
  std::int32_t i32() { return static_cast<std::int32_t>(u32()); }
  std::int64_t i64() { return static_cast<std::int64_t>(u64()); }
  float f32();
  double f64();
  std::string str();
  void raw(void* out, std::size_t n);
  std::vector<float> floats();
  std::vector<int> ints();
  // A count of elements each at least `element_bytes` long, checked against the bytes left.
  std::size_t count(std::size_t element_bytes);

  std::size_t remaining() const { return bytes_.size() - pos_; }
  bool at_end() const { return pos_ == bytes_.size(); }

 private:
  const char* take(std::size_t n);
  std::string_view bytes_;
  std::size_t pos_ = 0;
};

// One value, prefixed with its type; monostate is allowed (an unset optional output).
void write_value(ByteWriter& out, const PortValue& value);
PortValue read_value(ByteReader& in);

// Convenience: a whole byte string holding exactly one value.
std::string serialize_value(const PortValue& value);
PortValue deserialize_value(std::string_view bytes);

}  // namespace orogen
