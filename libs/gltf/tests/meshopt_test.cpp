// EXT_meshopt_compression: every compressed view decodes (meshoptimizer's own decoders, as
// three.js's MeshoptDecoder runs them) to exactly the bytes of the uncompressed file (triangles up
// to a rotation of their corners, which the index codec may apply), the file is
// smaller and validator-clean; and optimize_primitive() reorders without changing what is drawn.
#include <gtest/gtest.h>
#include <meshoptimizer.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <set>

#include "libs/gltf/optimize.h"
#include "libs/gltf/scene.h"
#include "libs/gltf/writer.h"
#include "tests/support/gltf_validator.h"
#include "tests/support/test_support.h"

namespace sylva::gltf {
namespace {

struct Glb {
  nlohmann::json json;
  std::string bin;
};

Glb parse_glb(const std::string& b) {
  auto le32 = [&](std::size_t at) {
    std::uint32_t v = 0;
    std::memcpy(&v, b.data() + at, 4);
    return static_cast<std::size_t>(v);
  };
  Glb out;
  EXPECT_EQ(b.substr(0, 4), "glTF");
  EXPECT_EQ(le32(8), b.size());
  const std::size_t json_len = le32(12);
  out.json = nlohmann::json::parse(b.substr(20, json_len));
  if (20 + json_len + 8 <= b.size()) out.bin = b.substr(20 + json_len + 8, le32(20 + json_len));
  return out;
}

// A wavy n x n grid of triangles (shuffled, so the optimisers have work) and a polyline.
Scene sample(int n) {
  Scene s;
  Mesh m;
  Primitive t;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const float x = float(i) / float(n), z = float(j) / float(n);
      t.positions.insert(t.positions.end(), {x, 0.1f * std::sin(7 * x) * std::cos(5 * z), z});
      t.normals.insert(t.normals.end(), {0, 1, 0});
      t.texcoords.insert(t.texcoords.end(), {x, z});
    }
  std::vector<std::array<std::uint32_t, 3>> tris;
  const auto at = [n](int i, int j) { return std::uint32_t(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      tris.push_back({at(i, j), at(i, j + 1), at(i + 1, j + 1)});
      tris.push_back({at(i, j), at(i + 1, j + 1), at(i + 1, j)});
    }
  for (std::size_t k = 0; k < tris.size(); ++k) std::swap(tris[k], tris[(k * 7919) % tris.size()]);
  for (const auto& tr : tris) t.indices.insert(t.indices.end(), tr.begin(), tr.end());
  m.primitives.push_back(t);
  Primitive l;
  l.mode = PrimitiveMode::kLines;
  for (int i = 0; i < 40; ++i) {
    l.positions.insert(l.positions.end(), {0, 0.05f * float(i), 0});
    l.colors.insert(l.colors.end(), {1, 1, 1, 0.5f + 0.01f * float(i)});
    if (i) l.indices.insert(l.indices.end(), {std::uint32_t(i - 1), std::uint32_t(i)});
  }
  m.primitives.push_back(l);
  s.meshes.push_back(m);
  Node node;
  node.mesh = 0;
  s.nodes.push_back(node);
  s.roots = {0};
  return s;
}

// Index triples, each rotated to start at its smallest index, as a multiset.
std::multiset<std::array<std::uint32_t, 3>> rotated_triangles(const std::string& bytes, std::size_t stride) {
  std::vector<std::uint32_t> idx(bytes.size() / stride);
  for (std::size_t i = 0; i < idx.size(); ++i) {
    std::uint32_t v = 0;
    std::memcpy(&v, bytes.data() + i * stride, stride);
    idx[i] = v;
  }
  std::multiset<std::array<std::uint32_t, 3>> out;
  for (std::size_t k = 0; k + 2 < idx.size(); k += 3) {
    const std::size_t r =
        idx[k] <= idx[k + 1] && idx[k] <= idx[k + 2] ? 0 : (idx[k + 1] <= idx[k + 2] ? 1 : 2);
    out.insert({idx[k + r], idx[k + (r + 1) % 3], idx[k + (r + 2) % 3]});
  }
  return out;
}

TEST(GltfMeshopt, ViewsDecodeToTheUncompressedBytes) {
  const Scene s = sample(40);
  const std::string plain = encode(s);
  WriteOptions o;
  o.meshopt = true;
  const std::string packed = encode(s, o);
  EXPECT_EQ(encode(s, o), packed);  // deterministic
  EXPECT_LT(packed.size(), plain.size() * 3 / 4);
  const Glb a = parse_glb(plain), b = parse_glb(packed);
  EXPECT_EQ(b.json["extensionsRequired"], nlohmann::json::array({"EXT_meshopt_compression"}));
  ASSERT_EQ(b.json["buffers"].size(), 2u);
  EXPECT_EQ(b.json["buffers"][1]["extensions"]["EXT_meshopt_compression"]["fallback"], true);
  EXPECT_FALSE(b.json["buffers"][1].contains("uri"));
  EXPECT_EQ(b.json["buffers"][0]["byteLength"], b.bin.size());
  ASSERT_EQ(a.json["bufferViews"].size(), b.json["bufferViews"].size());
  std::set<std::string> modes;
  for (std::size_t v = 0; v < a.json["bufferViews"].size(); ++v) {
    const auto& va = a.json["bufferViews"][v];
    const auto& vb = b.json["bufferViews"][v];
    ASSERT_TRUE(vb.contains("extensions")) << v;
    const auto& e = vb["extensions"]["EXT_meshopt_compression"];
    const std::size_t count = e["count"], stride = e["byteStride"];
    const std::size_t length = va["byteLength"];
    EXPECT_EQ(vb["byteLength"], length);
    EXPECT_EQ(vb["buffer"], 1);
    EXPECT_EQ(count * stride, length);
    const auto* src = reinterpret_cast<const unsigned char*>(b.bin.data()) + std::size_t(e["byteOffset"]);
    const std::size_t size = e["byteLength"];
    std::string out(length, '\0');
    const std::string mode = e["mode"];
    modes.insert(mode);
    int rc = -1;
    if (mode == "ATTRIBUTES") rc = meshopt_decodeVertexBuffer(out.data(), count, stride, src, size);
    if (mode == "TRIANGLES") rc = meshopt_decodeIndexBuffer(out.data(), count, stride, src, size);
    if (mode == "INDICES") rc = meshopt_decodeIndexSequence(out.data(), count, stride, src, size);
    ASSERT_EQ(rc, 0) << v << " " << mode;
    const std::string expected = a.bin.substr(va.value("byteOffset", std::size_t(0)), length);
    if (mode == "TRIANGLES") {
      // The index codec may rotate a triangle's corners (winding kept): compare rotated triples.
      EXPECT_EQ(rotated_triangles(out, stride), rotated_triangles(expected, stride)) << v;
    } else {
      EXPECT_TRUE(out == expected) << v << " " << mode << ": decoded bytes differ";
    }
  }
  EXPECT_EQ(modes, (std::set<std::string>{"ATTRIBUTES", "TRIANGLES", "INDICES"}));
  test::TempDir dir;
  test::write_file(dir / "m.glb", packed);
  SYLVA_EXPECT_VALID_GLTF(dir / "m.glb");
}

TEST(GltfMeshopt, OnlyGlbWithoutDraco) {
  WriteOptions o;
  o.meshopt = true;
  o.format = FileFormat::kGltf;
  EXPECT_THROW(encode(sample(2), o), GltfError);
  o.format = FileFormat::kGlb;
  o.draco.enabled = true;
  EXPECT_THROW(encode(sample(2), o), GltfError);
}

// The triangles as (vertex position triple) sets, each rotated to start at its smallest corner:
// winding kept, order ignored.
std::multiset<std::array<float, 9>> triangles(const Primitive& p) {
  std::multiset<std::array<float, 9>> out;
  for (std::size_t k = 0; k + 2 < p.indices.size(); k += 3) {
    std::array<std::array<float, 3>, 3> c;
    for (int v = 0; v < 3; ++v)
      for (int d = 0; d < 3; ++d) c[v][d] = p.positions[3 * p.indices[k + v] + d];
    const auto first = std::min_element(c.begin(), c.end()) - c.begin();
    std::array<float, 9> t;
    for (int v = 0; v < 3; ++v)
      for (int d = 0; d < 3; ++d) t[3 * v + d] = c[(first + v) % 3][d];
    out.insert(t);
  }
  return out;
}

TEST(GltfOptimize, SameTrianglesBetterCacheAndFetchOrder) {
  Scene s = sample(30);
  const Primitive before = s.meshes[0].primitives[0];
  optimize_scene(s);
  const Primitive& after = s.meshes[0].primitives[0];
  EXPECT_EQ(triangles(after), triangles(before));
  EXPECT_EQ(after.vertex_count(), before.vertex_count());
  EXPECT_EQ(after.texcoords.size(), before.texcoords.size());
  const auto acmr = [](const Primitive& p) {
    return meshopt_analyzeVertexCache(p.indices.data(), p.indices.size(), p.vertex_count(), 16, 0, 0).acmr;
  };
  EXPECT_LT(acmr(after), 0.8 * acmr(before));
  // Fetch order: vertices appear in first-use order.
  std::uint32_t next = 0;
  for (std::uint32_t i : after.indices) {
    EXPECT_LE(i, next);
    if (i == next) ++next;
  }
  // Lines: the same segments, vertices in first-use order.
  const Primitive& lines = s.meshes[0].primitives[1];
  EXPECT_EQ(lines.indices.size(), 78u);
  EXPECT_EQ(lines.colors.size(), 160u);
}

}  // namespace
}  // namespace sylva::gltf
