#include "nodes/io/gltf_bytes.h"

#include <cstdint>
#include <cstring>
#include <new>
#include <sstream>
#include <stdexcept>
#include <string>

#include <sys/mman.h>
#include <tiny_gltf.h>

#include "nodes/io/block_writer.h"
#include "nodes/io/file_error.h"

namespace orogen {

std::size_t GltfBuffer::add(std::size_t bytes, Emit emit) {
  const std::size_t offset = (size_ + 3) / 4 * 4;
  segments_.push_back({offset, bytes, std::move(emit)});
  size_ = offset + bytes;
  return offset;
}

void GltfBuffer::emit(const Sink& sink) const {
  static const char zeros[4] = {0, 0, 0, 0};
  std::size_t at = 0;
  for (const Segment& s : segments_) {
    if (s.offset > at) sink(zeros, s.offset - at);
    std::size_t got = 0;
    s.emit([&](const void* data, std::size_t bytes) {
      got += bytes;
      if (got > s.bytes) throw std::logic_error("glTF buffer segment emits more bytes than it declared");
      sink(data, bytes);
    });
    if (got != s.bytes) throw std::logic_error("glTF buffer segment emits fewer bytes than it declared");
    at = s.offset + s.bytes;
  }
}

namespace {

// Base64 (RFC 4648, '=' padded, as tinygltf encodes buffers) into the output block, streamed.
class Base64Out {
 public:
  explicit Base64Out(BlockWriter& out) : out_(out) {}
  void put(const unsigned char* p, std::size_t n) {
    while (n > 0 && carry_n_ > 0 && carry_n_ < 3) carry_[carry_n_++] = *p++, --n;
    if (carry_n_ == 3) {
      encode(carry_, 1);
      carry_n_ = 0;
    }
    const std::size_t whole = n / 3;
    for (std::size_t done = 0; done < whole;) {
      const std::size_t k = std::min<std::size_t>(whole - done, BlockWriter::kMaxRoom / 4);
      encode(p + 3 * done, k);
      done += k;
    }
    p += 3 * whole, n -= 3 * whole;
    while (n > 0) carry_[carry_n_++] = *p++, --n;
  }
  void finish() {
    if (carry_n_ == 0) return;
    static constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    const unsigned b0 = carry_[0], b1 = carry_n_ > 1 ? carry_[1] : 0;
    char s[4] = {kAlphabet[b0 >> 2], kAlphabet[((b0 & 3) << 4) | (b1 >> 4)],
                 carry_n_ > 1 ? kAlphabet[(b1 & 15) << 2] : '=', '='};
    out_.put(s, 4);
    carry_n_ = 0;
  }

 private:
  // `groups` groups of 3 bytes (at most kMaxRoom / 4) to 4 characters each.
  void encode(const unsigned char* p, std::size_t groups) {
    static constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    char* o = out_.room();
    for (std::size_t g = 0; g < groups; ++g, p += 3, o += 4) {
      const std::uint32_t v = (std::uint32_t(p[0]) << 16) | (std::uint32_t(p[1]) << 8) | p[2];
      o[0] = kAlphabet[v >> 18], o[1] = kAlphabet[(v >> 12) & 63], o[2] = kAlphabet[(v >> 6) & 63];
      o[3] = kAlphabet[v & 63];
    }
    out_.advance(4 * groups);
  }

  BlockWriter& out_;
  unsigned char carry_[3] = {0, 0, 0};
  int carry_n_ = 0;
};

void put_u32(BlockWriter& out, std::uint32_t v) { out.put(&v, 4); }  // little-endian hosts only

// Replaces the first occurrence of `from` in `s` (which must be there) by `to`.
void replace_once(std::string& s, const std::string& from, const std::string& to) {
  const std::size_t at = s.find(from);
  if (at == std::string::npos) throw std::logic_error("glTF buffer entry not found in tinygltf's document");
  s.replace(at, from.size(), to);
}

// tinygltf builds the whole document as an nlohmann::json tree before it prints it: about 1.75 KiB per node and
// 5.5 times the text's size (measured: 445 MB for a scene of 255 k instance nodes, 81 MB of JSON). Debian's
// libtinygltf is built with assertions on, and a std::bad_alloc thrown inside nlohmann's operator[] leaves an
// object without its map, whose destructor then aborts the process instead of failing the node. So the address
// space the tree needs, with a margin, is reserved and released first (PROT_NONE and MAP_NORESERVE: no memory is
// committed, but a limit on the address space, `ulimit -v`, counts it), and a scene that cannot have it fails
// here, cleanly. It is a check, not a reservation: another thread may take the space in between, so the abort
// becomes unlikely, not impossible, until tinygltf can serialize without its tree.
void require_room_for_document(const tinygltf::Model& model, const std::filesystem::path& path) {
  const std::size_t objects = model.nodes.size() + model.accessors.size() + model.bufferViews.size() +
                              model.meshes.size() + model.materials.size() + 64;
  const std::size_t bytes = objects * 2560;
  void* room = ::mmap(nullptr, bytes, PROT_NONE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
  if (room == MAP_FAILED)
    throw FileError("cannot write '" + path.string() + "': out of memory: serializing its glTF document needs about " +
                    std::to_string(bytes >> 20) + " MiB of address space that this process cannot have");
  ::munmap(room, bytes);
}

}  // namespace

void write_gltf_model(const tinygltf::Model& model, const GltfBuffer& buffer, const std::filesystem::path& path,
                      bool binary, const std::function<void(double)>& progress) {
  // tinygltf serializes the document with buffer 0 empty ("byteLength": 0, and in .gltf an empty data URI);
  // the length is put in and the data written around it. The patterns cannot occur inside a JSON string (every
  // quote in one is escaped), so the first match is the buffer's entry.
  require_room_for_document(model, path);
  std::string doc;
  try {
    std::ostringstream s;
    tinygltf::TinyGLTF writer;
    if (!writer.WriteGltfSceneToStream(&model, s, !binary, binary))
      throw FileError("cannot write '" + path.string() + "': glTF serialization failed");
    doc = std::move(s).str();
  } catch (const FileError&) {
    throw;
  } catch (const std::bad_alloc&) {
    throw FileError("cannot write '" + path.string() + "': out of memory while serializing the glTF file");
  } catch (const std::exception& e) {
    throw FileError("cannot write '" + path.string() + "': glTF serialization failed: " + e.what());
  }
  const std::size_t n = buffer.size();
  std::size_t total = 0;
  std::string json, tail;
  if (binary) {
    std::uint32_t length = 0;
    std::memcpy(&length, doc.data() + 12, 4);
    json = doc.substr(20, length);
    while (!json.empty() && json.back() == ' ') json.pop_back();  // the chunk's padding
    if (n)
      replace_once(json, "\"buffers\":[{\"byteLength\":0}]",
                   "\"buffers\":[{\"byteLength\":" + std::to_string(n) + "}]");
    total = 12 + 8 + (json.size() + 3) / 4 * 4 + (n ? 8 + (n + 3) / 4 * 4 : 0);
  } else {
    json = std::move(doc);
    if (n) {
      const std::string uri = "\"uri\": \"data:application/octet-stream;base64,\"";
      const std::size_t at = json.find(uri);
      const std::size_t length_at = at == std::string::npos ? at : json.rfind("\"byteLength\": 0", at);
      if (length_at == std::string::npos) throw std::logic_error("glTF buffer entry not found in tinygltf's document");
      const std::size_t split = at + uri.size() - 1;  // before the URI's closing quote
      tail = json.substr(split);
      json.resize(split);
      json.replace(length_at, 15, "\"byteLength\": " + std::to_string(n));
    }
    total = json.size() + (n + 2) / 3 * 4 + tail.size();
  }
  BlockWriter out(path, [&] {
    if (progress) progress(total ? static_cast<double>(out.bytes()) / static_cast<double>(total) : 1.0);
  });
  if (binary) {
    const std::uint32_t json_padded = static_cast<std::uint32_t>((json.size() + 3) / 4 * 4);
    out.put("glTF", 4);
    put_u32(out, 2);
    put_u32(out, static_cast<std::uint32_t>(total));
    put_u32(out, json_padded);
    put_u32(out, 0x4E4F534A);  // "JSON"
    out.put(json);
    out.put("   ", json_padded - json.size());
    if (n) {
      const auto bin_padded = static_cast<std::uint32_t>((n + 3) / 4 * 4);
      put_u32(out, bin_padded);
      put_u32(out, 0x004E4942);  // "BIN"
      buffer.emit([&](const void* data, std::size_t bytes) { out.put(data, bytes); });
      static const char zeros[4] = {0, 0, 0, 0};
      out.put(zeros, bin_padded - n);
    }
  } else {
    out.put(json);
    if (n) {
      Base64Out b64(out);
      buffer.emit(
          [&](const void* data, std::size_t bytes) { b64.put(static_cast<const unsigned char*>(data), bytes); });
      b64.finish();
      out.put(tail);
    }
  }
  if (out.bytes() != total) throw std::logic_error("glTF file size differs from the size computed for it");
  out.finish();
}

}  // namespace orogen
