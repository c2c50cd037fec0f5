// Cache building blocks: the canonical key hasher, value serialization of every port type, the LRU memory
// cache, the checksummed disk cache, and the key checks node tests use.
#include <cstdlib>
#include <cstring>
#include <fstream>

#include <gtest/gtest-spi.h>
#include <gtest/gtest.h>
#include <xxhash.h>

#include "evaluator/cache_key.h"
#include "evaluator/disk_cache.h"
#include "evaluator/evaluator.h"
#include "evaluator/memory_cache.h"
#include "evaluator/value_serialization.h"
#include "graph/exec_context.h"
#include "graph/mesh.h"
#include "graph/registry.h"
#include "support/key_checks.h"
#include "support/test_paths.h"

namespace orogen {

// A node with one parameter of every type and an input of every port type, for the key checks.
OROGEN_NODE(TestEveryParam) {
  b.category("test").description("Declares one parameter of every type; never evaluated.");
  for (PortType t : kAllPortTypes) b.input("in_" + std::string(to_string(t)), t).description("An input");
  b.input("optional_field", PortType::Heightfield).optional().description("An optional input");
  b.output("out", PortType::Heightfield).description("Nothing");
  b.param_float("float", 0.5).range(0.0, 1.0).unit(Unit::Metre).description("A float");
  b.param_float("unbounded", 0.0).unit(Unit::Unitless).description("A float without bounds");
  b.param_float("at_max", 10.0).unit(Unit::Unitless).range(0.0, 10.0).description("A float at its maximum");
  b.param_int("int", 3).unit(Unit::Count).range(1, 16).description("An int");
  b.param_int("int_at_min", 1).unit(Unit::Count).range(1, 16).description("An int at its minimum");
  b.param_bool("bool", false).description("A bool");
  b.param_vec2("vec2", {1.0, 2.0}).range(-10, 10).unit(Unit::Metre).description("A vec2");
  b.param_vec3("vec3", {0.0, 0.0, 1.0}).unit(Unit::Unitless).description("A vec3");
  b.param_color("color", {0.2f, 0.4f, 0.6f, 1.0f}).description("A color");
  b.param_enum("enum", {"one", "two", "three"}, "two").description("An enum");
  b.param_string("string", "").description("A string");
  b.param_path("path", "file.exr").extensions({".exr", ".png"}).description("A path");
  b.param_seed("seed", 7).description("A seed");
  b.param_curve("curve", CurveValue::identity()).description("A curve");
  b.param_gradient("gradient", GradientValue{{{0.0, {0, 0, 0, 1}}, {1.0, {1, 1, 1, 1}}}}).description("A gradient");
  b.execute([](ExecContext&) { throw NodeError("not evaluable"); });
}

OROGEN_NODE(TestDomainFree) {
  b.category("test").description("A domain-independent node; never evaluated.");
  b.domain_independent();
  b.output("out", PortType::Mesh).description("Nothing");
  b.param_float("size", 1.0).range(0.1, 10.0).unit(Unit::Metre).description("A size");
  b.execute([](ExecContext&) { throw NodeError("not evaluable"); });
}

namespace {

// --- keys ---------------------------------------------------------------------------------------------------

CacheKey key_of_bytes(const std::vector<unsigned char>& bytes) {
  const XXH128_hash_t h = XXH3_128bits(bytes.data(), bytes.size());
  return {h.high64, h.low64};
}

TEST(CacheKey, HexRoundTrip) {
  const CacheKey k{0x0123456789abcdefull, 0xfedcba9876543210ull};
  EXPECT_EQ(k.hex(), "0123456789abcdeffedcba9876543210");
  EXPECT_EQ(CacheKey::from_hex(k.hex()), k);
  EXPECT_EQ(CacheKey::from_hex("0123456789ABCDEFFEDCBA9876543210"), k);
  EXPECT_EQ(CacheKey{}.hex(), std::string(32, '0'));
  EXPECT_THROW(CacheKey::from_hex("0123"), std::invalid_argument);
  EXPECT_THROW(CacheKey::from_hex("0123456789abcdeffedcba987654321g"), std::invalid_argument);
}

TEST(KeyHasher, EncodingIsTheDocumentedTaggedStream) {
  // A string is tag 's', its length as 8 little-endian bytes, then its bytes: pinned so keys (and the disk
  // cache) stay stable across versions of the code.
  KeyHasher h;
  h.add(std::string_view("abc"));
  EXPECT_EQ(h.finish(), key_of_bytes({'s', 3, 0, 0, 0, 0, 0, 0, 0, 'a', 'b', 'c'}));
  KeyHasher i;
  i.add(std::int64_t{-2});
  EXPECT_EQ(i.finish(), key_of_bytes({'i', 0xfe, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff}));
  KeyHasher d;
  d.add(1.0);
  EXPECT_EQ(d.finish(), key_of_bytes({'d', 0, 0, 0, 0, 0, 0, 0xf0, 0x3f}));
}

TEST(KeyHasher, LongStreamsGiveTheDigestOfTheWholeStream) {
  // Many small values (crossing the hasher's internal batches) and one value longer than a batch.
  std::vector<unsigned char> expected;
  KeyHasher h;
  for (std::int64_t v = 0; v < 300; ++v) {
    h.add(v);
    expected.push_back('i');
    for (int b = 0; b < 8; ++b)
      expected.push_back(static_cast<unsigned char>(static_cast<std::uint64_t>(v) >> (8 * b)));
  }
  const std::string big(3000, 'x');
  h.add(std::string_view(big));
  expected.push_back('s');
  for (int b = 0; b < 8; ++b) expected.push_back(static_cast<unsigned char>(big.size() >> (8 * b)));
  expected.insert(expected.end(), big.begin(), big.end());
  h.add(std::string_view());  // an empty string still writes its tag and length
  expected.push_back('s');
  expected.insert(expected.end(), 8, 0);
  EXPECT_EQ(h.finish(), key_of_bytes(expected));
  EXPECT_EQ(h.finish(), key_of_bytes(expected)) << "finish() can be called again";
}

CacheKey hash(const std::function<void(KeyHasher&)>& f) {
  KeyHasher h;
  f(h);
  return h.finish();
}

TEST(KeyHasher, DistinctValuesGiveDistinctStreams) {
  EXPECT_NE(hash([](auto& h) { h.add(std::int64_t{1}); }), hash([](auto& h) { h.add(std::uint64_t{1}); }));
  EXPECT_NE(hash([](auto& h) { h.add(std::int64_t{1}); }), hash([](auto& h) { h.add(1.0); }));
  EXPECT_NE(hash([](auto& h) { h.add(true); }), hash([](auto& h) { h.add(std::int64_t{1}); }));
  EXPECT_NE(hash([](auto& h) { h.add(std::string_view("ab")).add(std::string_view("c")); }),
            hash([](auto& h) { h.add(std::string_view("a")).add(std::string_view("bc")); }));
  EXPECT_NE(hash([](auto& h) { h.add(ParamValue{std::int64_t{3}}); }),
            hash([](auto& h) { h.add(ParamValue{std::uint64_t{3}}); }));
  EXPECT_NE(hash([](auto& h) { h.add(CacheKey{1, 2}); }), hash([](auto& h) { h.add(CacheKey{2, 1}); }));
  Domain a = Domain::from_extent({0, 0}, {10, 10}, {8, 8});
  Domain b = a;
  b.first.x = 1;
  EXPECT_NE(hash([&](auto& h) { h.add(a); }), hash([&](auto& h) { h.add(b); }));
  // Equal values, equal keys: -0.0 == 0.0, and the same stream twice.
  EXPECT_EQ(hash([](auto& h) { h.add(-0.0); }), hash([](auto& h) { h.add(0.0); }));
  EXPECT_EQ(hash([&](auto& h) { h.add(a); }), hash([&](auto& h) { h.add(a); }));
}

TEST(KeyHasher, EveryParamValueAlternativeIsHashedByContent) {
  const std::vector<std::pair<ParamValue, ParamValue>> pairs = {
      {true, false},
      {std::int64_t{5}, std::int64_t{6}},
      {2.5, 2.5000001},
      {glm::dvec2{1, 2}, glm::dvec2{1, 3}},
      {glm::dvec3{1, 2, 3}, glm::dvec3{1, 2, 4}},
      {glm::vec4{0.1f, 0.2f, 0.3f, 1.0f}, glm::vec4{0.1f, 0.2f, 0.3f, 0.5f}},
      {std::string("perlin"), std::string("worley")},
      {std::uint64_t{42}, std::uint64_t{43}},
      {CurveValue{{{0, 0}, {1, 1}}}, CurveValue{{{0, 0}, {1, 0.9}}}},
      {GradientValue{{{0.0, {0, 0, 0, 1}}}}, GradientValue{{{0.0, {0, 0, 0.1f, 1}}}}},
  };
  for (const auto& [x, y] : pairs) {
    EXPECT_EQ(hash([&](auto& h) { h.add(x); }), hash([&](auto& h) { h.add(ParamValue(x)); })) << describe(x);
    EXPECT_NE(hash([&](auto& h) { h.add(x); }), hash([&](auto& h) { h.add(y); }))
        << describe(x) << " vs " << describe(y);
  }
  // Curves with the same points split differently must differ.
  EXPECT_NE(hash([](auto& h) {
              h.add(ParamValue{CurveValue{{{0, 0}}}}).add(ParamValue{CurveValue{{{1, 1}}}});
            }),
            hash([](auto& h) {
              h.add(ParamValue{CurveValue{{{0, 0}, {1, 1}}}});
            }));
}

TEST(KeyChecks, EveryParamAndInputOfADeclarationChangesTheKey) {
  const Domain d = Domain::from_extent({0, 0}, {500, 500}, {32, 32});
  expect_every_param_changes_key("TestEveryParam", d);
  expect_every_input_changes_key("TestEveryParam", d);
  expect_every_param_changes_key("TestDomainFree", d);
  expect_every_param_changes_key("Constant", d);
  expect_every_input_changes_key("Constant", d);
}

TEST(KeyChecks, UnknownTypeIsReported) {
  EXPECT_NONFATAL_FAILURE(expect_every_param_changes_key("NoSuchNodeType", Domain{}), "no registered node type");
  EXPECT_NONFATAL_FAILURE(expect_every_input_changes_key("NoSuchNodeType", Domain{}), "no registered node type");
}

// --- value serialization ------------------------------------------------------------------------------------

template <class T>
std::shared_ptr<const T> round_trip(const std::shared_ptr<const T>& value) {
  const std::string bytes = serialize_value(PortValue(value));
  const PortValue back = deserialize_value(bytes);
  EXPECT_EQ(serialize_value(back), bytes) << "serializing the decoded value gives the same bytes";
  const auto* p = std::get_if<std::shared_ptr<const T>>(&back);
  EXPECT_TRUE(p && *p);
  return p ? *p : nullptr;
}

// Every prefix of a valid encoding is rejected cleanly (never a crash, never a huge allocation).
void expect_prefixes_rejected(const PortValue& value, std::size_t stride = 1) {
  const std::string bytes = serialize_value(value);
  for (std::size_t n = 0; n < bytes.size(); n += stride)
    EXPECT_THROW(deserialize_value(std::string_view(bytes).substr(0, n)), SerializationError) << "prefix " << n;
  EXPECT_THROW(deserialize_value(bytes + "x"), SerializationError);
}

Domain odd_domain() {
  Domain d = Domain::from_extent({-12.5, 30.25}, {100.0, 60.0}, {7, 5});
  d.first = {3, -2};
  return d;
}

TEST(ValueSerialization, Heightfield) {
  auto h = std::make_shared<Heightfield>(odd_domain());
  for (std::size_t k = 0; k < h->data.size(); ++k) h->data[k] = static_cast<float>(k) * 0.37f - 5.0f;
  h->data[3] = -0.0f;
  const auto back = round_trip<Heightfield>(h);
  ASSERT_TRUE(back);
  EXPECT_EQ(back->domain, h->domain);
  EXPECT_EQ(std::memcmp(back->data.data(), h->data.data(), h->data.size() * sizeof(float)), 0);
  expect_prefixes_rejected(HeightfieldPtr(h));
}

// Floats go as byte planes (lowest bytes of all values first), which zstd compresses better; every bit pattern
// comes back, NaN payloads and signed zeros included.
TEST(ValueSerialization, FloatsAreWrittenAsBytePlanesAndReadBackBitExact) {
  const std::vector<std::uint32_t> bits = {0x11223344u, 0xa1b2c3d4u, 0x7fc01234u, 0x80000000u, 0x00000001u};
  std::vector<float> values(bits.size());
  std::memcpy(values.data(), bits.data(), bits.size() * 4);
  ByteWriter w;
  w.floats(values);
  const std::string bytes = w.take();
  ASSERT_EQ(bytes.size(), 8 + 4 * bits.size());
  for (std::size_t plane = 0; plane < 4; ++plane)
    for (std::size_t i = 0; i < bits.size(); ++i)
      EXPECT_EQ(static_cast<unsigned char>(bytes[8 + plane * bits.size() + i]), (bits[i] >> (8 * plane)) & 0xffu)
          << plane << "," << i;
  ByteReader r(bytes);
  const std::vector<float> back = r.floats();
  EXPECT_TRUE(r.at_end());
  ASSERT_EQ(back.size(), values.size());
  EXPECT_EQ(std::memcmp(back.data(), values.data(), values.size() * 4), 0);
  // A count beyond the bytes is refused before anything is read.
  ByteReader short_read(std::string_view(bytes).substr(0, bytes.size() - 1));
  EXPECT_THROW(short_read.floats(), SerializationError);
}

TEST(ValueSerialization, Image) {
  auto im = std::make_shared<Image>(odd_domain(), 3);
  im->channel_names = {"R", "G", "B"};
  for (std::size_t k = 0; k < im->data.size(); ++k) im->data[k] = static_cast<float>(k % 17) / 16.0f;
  const auto back = round_trip<Image>(im);
  ASSERT_TRUE(back);
  EXPECT_EQ(back->domain, im->domain);
  EXPECT_EQ(back->channels, 3);
  EXPECT_EQ(back->channel_names, im->channel_names);
  EXPECT_EQ(back->data, im->data);
  expect_prefixes_rejected(ImagePtr(im), 3);
}

TEST(ValueSerialization, Points) {
  auto p = std::make_shared<Points>();
  for (int k = 0; k < 5; ++k) p->add({k * 1.5f, -k * 2.0f, 100.0f + k}, k % 3);
  p->rotation[2] = glm::quat(0.5f, 0.5f, -0.5f, 0.5f);
  p->scale[4] = {2.0f, 3.0f, 4.0f};
  auto& age = p->attribute("age");
  for (int k = 0; k < 5; ++k) age[static_cast<std::size_t>(k)] = k * 10.0f;
  p->attribute("density", 0.25f);
  const auto back = round_trip<Points>(p);
  ASSERT_TRUE(back);
  EXPECT_EQ(back->position, p->position);
  EXPECT_EQ(back->rotation, p->rotation);
  EXPECT_EQ(back->scale, p->scale);
  EXPECT_EQ(back->class_id, p->class_id);
  EXPECT_EQ(back->attributes, p->attributes);
  expect_prefixes_rejected(PointsPtr(p));
  // Arrays of different lengths are inconsistent and refused.
  auto bad = std::make_shared<Points>(*p);
  bad->class_id.pop_back();
  EXPECT_THROW(deserialize_value(serialize_value(PointsPtr(bad))), SerializationError);
}

TEST(ValueSerialization, Curves) {
  auto c = std::make_shared<Curves>();
  for (int k = 0; k < 3; ++k) {
    Curve curve;
    for (int v = 0; v < 4 + k; ++v) {
      curve.points.push_back({v * 10.0f, k * 5.0f, v * 0.5f});
      curve.width.push_back(1.0f + v);
    }
    curve.attributes["flow"] = std::vector<float>(curve.points.size(), static_cast<float>(k));
    curve.parent = k - 1;
    c->curves.push_back(std::move(curve));
  }
  const auto back = round_trip<Curves>(c);
  ASSERT_TRUE(back);
  ASSERT_EQ(back->curves.size(), 3u);
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_EQ(back->curves[k].points, c->curves[k].points);
    EXPECT_EQ(back->curves[k].width, c->curves[k].width);
    EXPECT_EQ(back->curves[k].attributes, c->curves[k].attributes);
    EXPECT_EQ(back->curves[k].parent, c->curves[k].parent);
  }
  expect_prefixes_rejected(CurvesPtr(c), 2);
  auto bad = std::make_shared<Curves>(*c);
  bad->curves[1].parent = 7;
  EXPECT_THROW(deserialize_value(serialize_value(CurvesPtr(bad))), SerializationError);
}

std::shared_ptr<Mesh> grid_mesh(int n) {
  auto m = std::make_shared<Mesh>();
  std::vector<TriMesh::VertexHandle> v;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      auto vh = m->mesh.add_vertex(TriMesh::Point(i * 2.0f, j * 3.0f, static_cast<float>((i * j) % 5)));
      m->mesh.set_color(vh, OpenMesh::Vec4f(i / float(n), j / float(n), 0.5f, 1.0f));
      v.push_back(vh);
    }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const auto a = v[static_cast<std::size_t>(j * (n + 1) + i)], b = v[static_cast<std::size_t>(j * (n + 1) + i + 1)];
      const auto c = v[static_cast<std::size_t>((j + 1) * (n + 1) + i)],
                 d = v[static_cast<std::size_t>((j + 1) * (n + 1) + i + 1)];
      m->mesh.add_face(a, b, d);
      m->mesh.add_face(a, d, c);
    }
  m->mesh.update_normals();
  return m;
}

TEST(ValueSerialization, Mesh) {
  const auto m = grid_mesh(4);
  const auto back = round_trip<Mesh>(m);
  ASSERT_TRUE(back);
  ASSERT_EQ(back->vertex_count(), m->vertex_count());
  ASSERT_EQ(back->face_count(), m->face_count());
  for (auto vh : m->mesh.vertices()) {
    const TriMesh::VertexHandle bv(vh.idx());
    EXPECT_EQ(back->mesh.point(bv), m->mesh.point(vh));
    EXPECT_EQ(back->mesh.normal(bv), m->mesh.normal(vh));
    EXPECT_EQ(back->mesh.color(bv), m->mesh.color(vh));
  }
  for (auto fh : m->mesh.faces()) {
    const TriMesh::FaceHandle bf(fh.idx());
    std::vector<int> a, b;
    for (auto vh : m->mesh.fv_range(fh)) a.push_back(vh.idx());
    for (auto vh : back->mesh.fv_range(bf)) b.push_back(vh.idx());
    EXPECT_EQ(a, b);
    EXPECT_EQ(back->mesh.normal(bf), m->mesh.normal(fh));
  }
  expect_prefixes_rejected(MeshPtr(m), 7);
}

TEST(ValueSerialization, MeshWithDeletedElementsIsCompacted) {
  auto m = grid_mesh(3);
  m->mesh.delete_vertex(TriMesh::VertexHandle(5));  // an interior vertex and its faces
  std::size_t live_vertices = 0, live_faces = 0;
  for ([[maybe_unused]] auto vh : m->mesh.vertices()) ++live_vertices;
  for ([[maybe_unused]] auto fh : m->mesh.faces()) ++live_faces;
  const auto back = std::get<MeshPtr>(deserialize_value(serialize_value(MeshPtr(m))));
  EXPECT_EQ(back->vertex_count(), live_vertices);
  EXPECT_EQ(back->face_count(), live_faces);
  EXPECT_LT(live_faces, m->face_count());
}

TEST(ValueSerialization, PolygonMap) {
  auto pm = std::make_shared<PolygonMap>();
  pm->min_corner = {-5.0, -5.0};
  pm->max_corner = {95.0, 45.0};
  // Two cells sharing one edge between corners 0 and 1.
  pm->corners = {{{10.0, 0.0}, {0, 1}, {1, 2}, {0, 1}, true},
                 {{10.0, 20.0}, {0, 1}, {0}, {0}, false},
                 {{0.0, 0.0}, {0}, {0}, {1}, true}};
  pm->cells = {{{5.0, 10.0}, {0, 1, 2}, {1}, {0, 1}, true}, {{15.0, 10.0}, {1, 0}, {0}, {0}, false}};
  pm->edges = {{{0, 1}, {0, 1}}, {{0, -1}, {0, 2}}};
  pm->cell_attributes["elevation"] = {0.5f, 1.5f};
  pm->corner_attributes["water"] = {0.0f, 1.0f, 0.0f};
  pm->edge_attributes["river"] = {3.0f, 0.0f};
  pm->check_consistent();
  const auto back = round_trip<PolygonMap>(pm);
  ASSERT_TRUE(back);
  EXPECT_EQ(back->min_corner, pm->min_corner);
  EXPECT_EQ(back->max_corner, pm->max_corner);
  ASSERT_EQ(back->cells.size(), 2u);
  ASSERT_EQ(back->corners.size(), 3u);
  ASSERT_EQ(back->edges.size(), 2u);
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_EQ(back->cells[k].centre, pm->cells[k].centre);
    EXPECT_EQ(back->cells[k].corners, pm->cells[k].corners);
    EXPECT_EQ(back->cells[k].neighbours, pm->cells[k].neighbours);
    EXPECT_EQ(back->cells[k].edges, pm->cells[k].edges);
    EXPECT_EQ(back->cells[k].border, pm->cells[k].border);
    EXPECT_EQ(back->edges[k].cells, pm->edges[k].cells);
    EXPECT_EQ(back->edges[k].corners, pm->edges[k].corners);
  }
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_EQ(back->corners[k].position, pm->corners[k].position);
    EXPECT_EQ(back->corners[k].cells, pm->corners[k].cells);
    EXPECT_EQ(back->corners[k].adjacent, pm->corners[k].adjacent);
    EXPECT_EQ(back->corners[k].edges, pm->corners[k].edges);
    EXPECT_EQ(back->corners[k].border, pm->corners[k].border);
  }
  EXPECT_EQ(back->cell_attributes, pm->cell_attributes);
  EXPECT_EQ(back->corner_attributes, pm->corner_attributes);
  EXPECT_EQ(back->edge_attributes, pm->edge_attributes);
  expect_prefixes_rejected(PolygonMapPtr(pm));
  auto bad = std::make_shared<PolygonMap>(*pm);
  bad->cells[0].corners.push_back(9);
  EXPECT_THROW(deserialize_value(serialize_value(PolygonMapPtr(bad))), SerializationError);
}

TEST(ValueSerialization, EmptyValuesAndGarbage) {
  EXPECT_TRUE(std::holds_alternative<std::monostate>(deserialize_value(serialize_value(std::monostate{}))));
  EXPECT_TRUE(round_trip<Points>(std::make_shared<Points>()));
  EXPECT_TRUE(round_trip<Curves>(std::make_shared<Curves>()));
  EXPECT_TRUE(round_trip<Mesh>(std::make_shared<Mesh>()));
  EXPECT_TRUE(round_trip<PolygonMap>(std::make_shared<PolygonMap>()));
  EXPECT_THROW(deserialize_value(std::string("\x09", 1)), SerializationError);  // unknown type tag
  // A huge element count is refused before allocating.
  ByteWriter w;
  w.u8(1);
  w.f64(0), w.f64(0), w.f64(1), w.f64(1);
  w.i32(0), w.i32(0), w.i32(1 << 20), w.i32(1 << 20);
  w.u64(std::uint64_t(1) << 40);
  EXPECT_THROW(deserialize_value(w.buffer()), SerializationError);
  // A sample count that does not match the domain.
  auto h = std::make_shared<Heightfield>(odd_domain());
  h->data.pop_back();
  EXPECT_THROW(deserialize_value(serialize_value(HeightfieldPtr(h))), SerializationError);
}

// --- memory cache -------------------------------------------------------------------------------------------

std::shared_ptr<const CachedResult> entry() { return std::make_shared<CachedResult>(); }
CacheKey key(std::uint64_t k) { return {k, ~k}; }

TEST(MemoryCache, EvictsLeastRecentlyUsedWithinTheByteBound) {
  MemoryCache c(300);
  EXPECT_TRUE(c.insert(key(1), entry(), 100));
  EXPECT_TRUE(c.insert(key(2), entry(), 100));
  EXPECT_TRUE(c.insert(key(3), entry(), 100));
  EXPECT_EQ(c.bytes(), 300u);
  EXPECT_TRUE(c.find(key(1)));  // 1 is now the most recent
  EXPECT_TRUE(c.insert(key(4), entry(), 100));
  EXPECT_FALSE(c.find(key(2))) << "2 was the least recently used";
  EXPECT_TRUE(c.find(key(1)));
  EXPECT_TRUE(c.find(key(3)));
  EXPECT_TRUE(c.find(key(4)));
  EXPECT_EQ(c.evictions(), 1u);
  EXPECT_TRUE(c.insert(key(5), entry(), 250));  // makes room by evicting two
  EXPECT_LE(c.bytes(), 300u);
  EXPECT_EQ(c.entries(), 1u);
  EXPECT_EQ(c.evictions(), 4u);
}

TEST(MemoryCache, ReplacesAndRefusesOversized) {
  MemoryCache c(100);
  const auto a = entry(), b = entry();
  EXPECT_TRUE(c.insert(key(1), a, 40));
  EXPECT_TRUE(c.insert(key(1), b, 60));
  EXPECT_EQ(c.entries(), 1u);
  EXPECT_EQ(c.bytes(), 60u);
  EXPECT_EQ(c.find(key(1)), b);
  EXPECT_FALSE(c.insert(key(2), entry(), 101));
  EXPECT_EQ(c.entries(), 1u);
  EXPECT_EQ(c.evictions(), 0u);
  c.erase(key(1));
  EXPECT_EQ(c.bytes(), 0u);
  c.insert(key(3), entry(), 10);
  c.clear();
  EXPECT_EQ(c.entries(), 0u);
  EXPECT_FALSE(c.find(key(3)));
}

// --- disk cache ---------------------------------------------------------------------------------------------

CachedResult sample_result() {
  CachedResult r;
  auto h = std::make_shared<Heightfield>(odd_domain(), 2.5f);
  r.outputs.push_back(HeightfieldPtr(h));
  r.outputs.push_back(MeshPtr(grid_mesh(2)));
  r.files.push_back({"out/height.exr", 1234, 5678});
  return r;
}

TEST(DiskCache, StoresAndLoads) {
  const DiskCache cache(test::scratch_dir("disk-cache"));
  const CacheKey k{0xabcdef, 0x123456};
  EXPECT_FALSE(cache.load(k).result);
  EXPECT_FALSE(cache.load(k).rejected);
  cache.store(k, sample_result());
  const auto path = cache.path_of(k);
  EXPECT_EQ(path.parent_path().filename(), k.hex().substr(0, 2));
  EXPECT_EQ(path.filename(), k.hex() + ".orc");
  ASSERT_TRUE(std::filesystem::exists(path));
  const auto loaded = cache.load(k);
  ASSERT_TRUE(loaded.result);
  ASSERT_EQ(loaded.result->outputs.size(), 2u);
  EXPECT_EQ(std::get<HeightfieldPtr>(loaded.result->outputs[0])->data, std::vector<float>(35, 2.5f));
  EXPECT_EQ(std::get<MeshPtr>(loaded.result->outputs[1])->face_count(), 8u);
  EXPECT_EQ(loaded.result->files, sample_result().files);
  // Nothing but the entry is left in the directory (no temporaries).
  std::size_t files = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::recursive_directory_iterator(cache.directory()))
    files += e.is_regular_file();
  EXPECT_EQ(files, 1u);
}

TEST(DiskCache, AValueIsWorthAnEntryWhenRecomputingItCostsMore) {
  ::unsetenv("OROGEN_CACHE_STORE");
  const DiskCache cache(test::scratch_dir("disk-cache-worth"));
  constexpr std::uint64_t kMiB = std::uint64_t(1) << 20;
  const double entry_ms = 64 * DiskCache::kStoreAndLoadMsPerMiB;  // writing and reading 64 MiB
  // Small values always: leaving them out would save next to nothing.
  EXPECT_TRUE(cache.worth_storing(0.0, DiskCache::kAlwaysStoredBytes - 1));
  EXPECT_FALSE(cache.worth_storing(0.0, DiskCache::kAlwaysStoredBytes));
  EXPECT_FALSE(cache.worth_storing(0.5 * entry_ms, 64 * kMiB));
  EXPECT_FALSE(cache.worth_storing(entry_ms, 64 * kMiB));
  EXPECT_TRUE(cache.worth_storing(1.01 * entry_ms, 64 * kMiB));
  EXPECT_TRUE(cache.worth_storing(1.01 * entry_ms / 64, kMiB));
  // OROGEN_CACHE_STORE=all keeps everything; any other value is the default.
  ASSERT_EQ(::setenv("OROGEN_CACHE_STORE", "all", 1), 0);
  const DiskCache all(cache.directory());
  ASSERT_EQ(::setenv("OROGEN_CACHE_STORE", "some", 1), 0);
  const DiskCache other(cache.directory());
  ::unsetenv("OROGEN_CACHE_STORE");
  EXPECT_TRUE(all.worth_storing(0.0, 64 * kMiB));
  EXPECT_FALSE(other.worth_storing(0.0, 64 * kMiB));
}

// A thread reuses its serialization and compression buffers from one store to the next: entries of every size,
// in any order, must each read back as stored (a stale tail of a larger entry would corrupt a smaller one).
TEST(DiskCache, StoresOfEverySizeInTurnReadBackExactly) {
  const DiskCache cache(test::scratch_dir("disk-cache-sizes"));
  const int sides[] = {300, 5, 120, 1, 300, 17};
  for (int n = 0; n < 6; ++n) {
    Domain d;
    d.resolution = {sides[n], sides[n] + 1};
    auto h = std::make_shared<Heightfield>(d);
    for (std::size_t k = 0; k < h->data.size(); ++k) h->data[k] = static_cast<float>((k * 2654435761u + n) % 1000);
    CachedResult r;
    r.outputs.push_back(HeightfieldPtr(h));
    cache.store(CacheKey{1, static_cast<std::uint64_t>(n)}, r);
  }
  for (int n = 0; n < 6; ++n) {
    const auto loaded = cache.load(CacheKey{1, static_cast<std::uint64_t>(n)});
    ASSERT_TRUE(loaded.result) << n << ": " << loaded.reason;
    const auto& h = *std::get<HeightfieldPtr>(loaded.result->outputs[0]);
    ASSERT_EQ(h.width(), sides[n]);
    for (std::size_t k = 0; k < h.data.size(); ++k)
      ASSERT_EQ(h.data[k], static_cast<float>((k * 2654435761u + n) % 1000)) << n << " at " << k;
  }
}

void expect_rejected_after(const std::function<void(const std::filesystem::path&)>& damage, const char* what) {
  const DiskCache cache(test::scratch_dir("disk-cache-bad"));
  const CacheKey k{77, 88};
  cache.store(k, sample_result());
  damage(cache.path_of(k));
  const auto loaded = cache.load(k);
  EXPECT_FALSE(loaded.result) << what;
  EXPECT_TRUE(loaded.rejected) << what;
  EXPECT_FALSE(loaded.reason.empty()) << what;
  EXPECT_FALSE(std::filesystem::exists(cache.path_of(k))) << what << ": a rejected entry is deleted";
}

void flip_byte(const std::filesystem::path& p, std::size_t offset) {
  std::fstream f(p, std::ios::in | std::ios::out | std::ios::binary);
  f.seekg(static_cast<std::streamoff>(offset));
  const char c = static_cast<char>(f.get());
  f.seekp(static_cast<std::streamoff>(offset));
  f.put(static_cast<char>(c ^ 0x10));
}

TEST(DiskCache, RejectsDamagedEntries) {
  expect_rejected_after([](const auto& p) { flip_byte(p, DiskCache::kHeaderBytes + 40); }, "payload byte flipped");
  expect_rejected_after([](const auto& p) { flip_byte(p, 0); }, "magic damaged");
  expect_rejected_after([](const auto& p) { flip_byte(p, 8); }, "container version changed");
  expect_rejected_after([](const auto& p) { flip_byte(p, 12); }, "value format version changed");
  expect_rejected_after([](const auto& p) { flip_byte(p, 17); }, "key in the header changed");
  expect_rejected_after([](const auto& p) { flip_byte(p, 33); }, "length changed");
  expect_rejected_after([](const auto& p) { flip_byte(p, 41); }, "checksum changed");
  expect_rejected_after([](const auto& p) { std::filesystem::resize_file(p, std::filesystem::file_size(p) - 1); },
                        "last byte cut");
  expect_rejected_after([](const auto& p) { std::filesystem::resize_file(p, 20); }, "header cut");
  expect_rejected_after([](const auto& p) { std::filesystem::resize_file(p, 0); }, "empty file");
  expect_rejected_after([](const auto& p) { std::ofstream(p, std::ios::app | std::ios::binary) << "extra"; },
                        "bytes appended");
}

TEST(DiskCache, ValidChecksumButUndecodablePayloadIsRejected) {
  // Written by hand: a correct header and checksum around a payload that is not a CachedResult.
  const DiskCache cache(test::scratch_dir("disk-cache-undecodable"));
  const CacheKey k{5, 6};
  ByteWriter body;
  body.u64(1);  // one output ...
  body.u8(7);   // ... with an unknown type tag
  const std::string payload = body.buffer();
  ByteWriter w;
  w.raw("OROGENC1", 8);
  w.u32(1);
  w.u32(kValueFormatVersion);
  w.u64(k.high);
  w.u64(k.low);
  w.u64(payload.size());
  w.u64(XXH3_64bits(payload.data(), payload.size()));
  w.raw(payload.data(), payload.size());
  std::filesystem::create_directories(cache.path_of(k).parent_path());
  std::ofstream(cache.path_of(k), std::ios::binary) << w.buffer();
  const auto loaded = cache.load(k);
  EXPECT_TRUE(loaded.rejected);
  EXPECT_NE(loaded.reason.find("undecodable"), std::string::npos) << loaded.reason;
}

}  // namespace
}  // namespace orogen
