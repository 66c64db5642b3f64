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

#include "libs/gltf/json_numbers.h"
#include "libs/gltf/optimize.h"
#include "libs/gltf/scene.h"
#include "libs/gltf/testing/rotated_triangles.h"
#include "libs/gltf/testing/sample_geometry.h"
#include "libs/gltf/writer.h"
#include "tests/support/gltf_fixtures.h"
#include "tests/support/gltf_validator.h"
#include "tests/support/test_support.h"

namespace sylva::gltf {
namespace {

using test::Glb;
using test::parse_glb;
using testing::rotated_triangles;

// A wavy n x n grid of triangles (shuffled, so the optimisers have work) and a polyline.
Scene sample(int n) {
  Scene s;
  Mesh m;
  Primitive t = testing::wavy_grid(n);
  const std::size_t tris = t.indices.size() / 3;
  for (std::size_t k = 0; k < tris; ++k)
    for (std::size_t c = 0; c < 3; ++c)
      std::swap(t.indices[3 * k + c], t.indices[3 * ((k * 7919) % tris) + c]);
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

// A meshopt file's numbers are as short as their floats (0.8f as 0.8, not the widened double's
// 0.800000011920929; 1.0 as 1), extras keep their doubles, triangles leave out their default
// mode, and the float positions' min/max still bound the data exactly as floats.
TEST(GltfMeshopt, NumbersAreAsShortAsTheirFloats) {
  for (const float f :
       {0.8f, 0.9f, 0.60382736f, -8.397303f, 1e-7f, 3.4e38f, 1.4e-45f, 16.003663f, 0.0016831488f}) {
    EXPECT_EQ(float(float_json(f)), f) << f;
    EXPECT_EQ(float_json(float_json(f)), float_json(f)) << f;
  }
  EXPECT_EQ(float_json(0.8f), 0.8);
  EXPECT_EQ(float_json(double(0.9f)), 0.9);
  Scene s = sample(6);
  Material m;
  m.name = "bark";
  m.base_color = {0.8f, 0.60382736f, 0.1f, 1};
  m.roughness = 0.9f;
  m.metallic = 0;
  s.materials.push_back(m);
  for (Primitive& p : s.meshes[0].primitives) p.material = 0;
  s.nodes[0].translation = {double(0.1f), 0, 0};
  s.nodes[0].extras = {{"switch_distance_m", double(0.8f)}};
  WriteOptions o;
  o.meshopt = true;  // float positions (no quantisation)
  const std::string bytes = encode(s, o);
  EXPECT_EQ(encode(s, o), bytes);  // deterministic
  const Glb g = parse_glb(bytes);
  const std::string json =
      bytes.substr(20, g.bin.empty() ? std::string::npos : bytes.size() - 20 - g.bin.size() - 8);
  EXPECT_NE(json.find("\"baseColorFactor\":[0.8,0.60382736,0.1,1]"), std::string::npos) << json;
  EXPECT_NE(json.find("\"roughnessFactor\":0.9}"), std::string::npos) << json;
  EXPECT_NE(json.find("\"metallicFactor\":0,"), std::string::npos) << json;
  EXPECT_NE(json.find("\"translation\":[0.1,0,0]"), std::string::npos) << json;
  EXPECT_EQ(json.find("0.800000011920929"), json.find("\"switch_distance_m\":0.800000011920929") + 20)
      << json;
  EXPECT_EQ(json.find("0.899999976"), std::string::npos) << json;
  const nlohmann::json& prims = g.json["meshes"][0]["primitives"];
  EXPECT_FALSE(prims[0].contains("mode"));
  EXPECT_EQ(prims[1]["mode"], 1);
  // POSITION: FLOAT, its min/max the data's extremes as floats.
  for (std::size_t p = 0; p < 2; ++p) {
    const nlohmann::json& a = g.json["accessors"][prims[p]["attributes"]["POSITION"].get<std::size_t>()];
    ASSERT_EQ(a["componentType"], 5126);
    const std::vector<float>& v = s.meshes[0].primitives[p].positions;
    for (std::size_t c = 0; c < 3; ++c) {
      float lo = v[c], hi = v[c];
      for (std::size_t i = c; i < v.size(); i += 3) lo = std::min(lo, v[i]), hi = std::max(hi, v[i]);
      EXPECT_EQ(float(a["min"][c].get<double>()), lo) << p << " " << c;
      EXPECT_EQ(float(a["max"][c].get<double>()), hi) << p << " " << c;
      EXPECT_EQ(a["max"][c].get<double>(), float_json(hi)) << p << " " << c;
    }
  }
  test::TempDir dir;
  test::write_file(dir / "m.glb", bytes);
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

// For size (the pack), lines keep their order: a branch's vertices along it, a joint repeated per
// segment, compress better than in first-use order (optimize.h); for the GPU they are fetch-ordered.
TEST(GltfOptimize, ForSizeLinesKeepTheirVertexOrder) {
  Scene s = sample(4);
  Primitive& l = s.meshes[0].primitives[1];
  // Segments listed back to front: first-use order would reverse the vertices.
  std::vector<std::uint32_t> reversed;
  for (std::size_t k = l.indices.size(); k >= 2; k -= 2)
    reversed.insert(reversed.end(), {l.indices[k - 2], l.indices[k - 1]});
  l.indices = reversed;
  const Primitive before = l;
  Scene gpu = s;
  optimize_scene(s, OptimizeOrder::kSize);
  EXPECT_EQ(s.meshes[0].primitives[1].positions, before.positions);
  EXPECT_EQ(s.meshes[0].primitives[1].indices, before.indices);
  optimize_scene(gpu, OptimizeOrder::kGpu);
  EXPECT_NE(gpu.meshes[0].primitives[1].positions, before.positions);
  EXPECT_EQ(gpu.meshes[0].primitives[1].indices[0], 0u);
}

// KHR_mesh_quantization (QuantizeOptions): the integers decode, through the node's transform,
// to within half a grid step of every input position; uvs and normals within their bits; the
// extension is required; with meshopt the normals go through the OCTAHEDRAL filter; every file
// is validator-clean.
template <typename T>
T read_at(const std::string& bin, std::size_t at) {
  T v;
  std::memcpy(&v, bin.data() + at, sizeof(T));
  return v;
}

TEST(GltfQuantize, PositionsOnTheMeshGridNormalsAndUvs) {
  Scene s = sample(20);
  for (auto& prim : s.meshes[0].primitives)
    for (float& p : prim.positions) p = 3.f * p - 1.f;
  double extent = 0;  // the largest axis extent over both primitives
  for (std::size_t c = 0; c < 3; ++c) {
    double lo = 1e9, hi = -1e9;
    for (const auto& prim : s.meshes[0].primitives)
      for (std::size_t i = c; i < prim.positions.size(); i += 3)
        lo = std::min<double>(lo, prim.positions[i]), hi = std::max<double>(hi, prim.positions[i]);
    extent = std::max(extent, hi - lo);
  }
  WriteOptions o;
  o.quantize.enabled = true;
  o.quantize.position_bits = {10};
  o.quantize.texcoord_bits = 12;
  const std::string bytes = encode(s, o);
  const Glb g = parse_glb(bytes);
  EXPECT_EQ(g.json["extensionsRequired"], nlohmann::json::array({"KHR_mesh_quantization"}));
  const auto& node = g.json["nodes"][0];
  const double step = node["scale"][0];
  EXPECT_DOUBLE_EQ(step, extent / 1023.0);
  EXPECT_EQ(node["scale"], nlohmann::json::array({step, step, step}));
  const Primitive& in = s.meshes[0].primitives[0];
  const auto& prim = g.json["meshes"][0]["primitives"][0];
  const auto& pos = g.json["accessors"][std::size_t(prim["attributes"]["POSITION"])];
  EXPECT_EQ(pos["componentType"], 5123);  // UNSIGNED_SHORT
  EXPECT_FALSE(pos.value("normalized", false));
  const auto& view = g.json["bufferViews"][std::size_t(pos["bufferView"])];
  EXPECT_EQ(view["byteStride"], 8);
  double worst = 0;
  for (std::size_t i = 0; i < in.vertex_count(); ++i)
    for (std::size_t c = 0; c < 3; ++c) {
      const double q =
          read_at<std::uint16_t>(g.bin, std::size_t(view.value("byteOffset", 0)) + i * 8 + c * 2);
      const double x = double(node["translation"][c]) + q * step;
      worst = std::max(worst, std::abs(x - in.positions[i * 3 + c]));
    }
  EXPECT_LE(worst, step / 2 * 1.0001);
  EXPECT_GT(worst, step / 10);  // really on the grid
  const auto& uv = g.json["accessors"][std::size_t(prim["attributes"]["TEXCOORD_0"])];
  EXPECT_EQ(uv["componentType"], 5123);
  EXPECT_TRUE(uv["normalized"].get<bool>());
  const auto& uv_view = g.json["bufferViews"][std::size_t(uv["bufferView"])];
  for (std::size_t i = 0; i < in.vertex_count(); ++i)
    for (std::size_t c = 0; c < 2; ++c) {
      const double q =
          read_at<std::uint16_t>(g.bin, std::size_t(uv_view.value("byteOffset", 0)) + i * 4 + c * 2);
      EXPECT_EQ(int(q) % 16, 0);  // 12-bit grid, low bits zero
      const double tol = in.texcoords[i * 2 + c] > 65520.0 / 65535 - 8.0 / 65535 ? 16.0 / 65535 : 8.0 / 65535;
      EXPECT_NEAR(q / 65535.0, in.texcoords[i * 2 + c], tol * 1.0001) << i;
    }
  const auto& n = g.json["accessors"][std::size_t(prim["attributes"]["NORMAL"])];
  EXPECT_EQ(n["componentType"], 5120);  // BYTE
  EXPECT_TRUE(n["normalized"].get<bool>());
  const auto& n_view = g.json["bufferViews"][std::size_t(n["bufferView"])];
  EXPECT_EQ(read_at<std::int8_t>(g.bin, std::size_t(n_view.value("byteOffset", 0)) + 1), 127);  // (0, 1, 0)
  // The line primitive's colours: UNSIGNED_BYTE normalized.
  const auto& lines = g.json["meshes"][0]["primitives"][1];
  EXPECT_EQ(g.json["accessors"][std::size_t(lines["attributes"]["COLOR_0"])]["componentType"], 5121);
  test::TempDir dir;
  test::write_file(dir / "q.glb", bytes);
  SYLVA_EXPECT_VALID_GLTF(dir / "q.glb");

  // meshopt: the same integers, normals octahedral through the filter.
  o.meshopt = true;
  const std::string packed = encode(s, o);
  const Glb m = parse_glb(packed);
  const auto& mn =
      m.json["bufferViews"][std::size_t(n["bufferView"])]["extensions"]["EXT_meshopt_compression"];
  EXPECT_EQ(mn["filter"], "OCTAHEDRAL");
  EXPECT_EQ(m.json["extensionsRequired"],
            nlohmann::json::array({"EXT_meshopt_compression", "KHR_mesh_quantization"}));
  const auto& mp =
      m.json["bufferViews"][std::size_t(pos["bufferView"])]["extensions"]["EXT_meshopt_compression"];
  const std::size_t count = mp["count"];
  std::string decoded(count * 8, '\0');
  ASSERT_EQ(meshopt_decodeVertexBuffer(
                decoded.data(), count, 8,
                reinterpret_cast<const unsigned char*>(m.bin.data()) + std::size_t(mp["byteOffset"]),
                mp["byteLength"]),
            0);
  EXPECT_TRUE(decoded == g.bin.substr(view.value("byteOffset", 0), decoded.size()));
  test::write_file(dir / "m.glb", packed);
  SYLVA_EXPECT_VALID_GLTF(dir / "m.glb");
  // Fewer bytes than lossless meshopt of the float attributes (this regular grid compresses
  // well as floats too; real trees: docs/performance.md).
  WriteOptions lossless;
  lossless.meshopt = true;
  EXPECT_LT(packed.size(), encode(s, lossless).size());
}

TEST(GltfQuantize, ChildrenOfAQuantisedNodeKeepTheirPlace) {
  Scene s = sample(4);
  s.nodes[0].translation = {1, 2, 3};
  Node child;
  child.translation = {0.5, 0, 0};
  s.nodes.push_back(child);
  s.nodes[0].children = {1};
  WriteOptions o;
  o.quantize.enabled = true;
  o.quantize.position_bits = {8};
  const Glb g = parse_glb(encode(s, o));
  const double step = g.json["nodes"][0]["scale"][0];
  const auto& t0 = g.json["nodes"][0]["translation"];
  const auto& t1 = g.json["nodes"][1]["translation"];
  const auto& s1 = g.json["nodes"][1]["scale"];
  // parent' * child' = parent * child: the child's world origin and scale are unchanged.
  EXPECT_NEAR(double(t0[0]) + step * double(t1[0]), 1.5, 1e-9);
  EXPECT_NEAR(double(t0[1]) + step * double(t1[1]), 2.0, 1e-9);
  EXPECT_NEAR(step * double(s1[0]), 1.0, 1e-12);
}

TEST(GltfQuantize, RefusesBitsOutOfRange) {
  WriteOptions o;
  o.quantize.enabled = true;
  o.quantize.position_bits = {17};
  try {
    encode(sample(2), o);
    FAIL();
  } catch (const GltfError& e) {
    EXPECT_STREQ(e.what(), "quantize.position_bits[0] is 17, expected 0..16");
  }
  o.quantize.position_bits = {};
  o.quantize.normal_bits = 0;
  EXPECT_THROW(encode(sample(2), o), GltfError);
}

// Float positions within a bound: meshopt's EXPONENTIAL filter with the fewest mantissa bits that
// keep every vertex within it (measured by decoding as a client does).
TEST(GltfQuantize, FloatPositionsThroughTheExponentialFilterStayWithinTheBound) {
  Scene s = sample(20);
  for (auto& prim : s.meshes[0].primitives)
    for (float& p : prim.positions) p = 30.f * p + 5.f;
  WriteOptions o;
  o.meshopt = true;
  o.quantize.enabled = true;
  o.quantize.float_position_error = {0.002};
  const std::string bytes = encode(s, o);
  const Glb g = parse_glb(bytes);
  const auto& prim = g.json["meshes"][0]["primitives"][0];
  const auto& pos = g.json["accessors"][std::size_t(prim["attributes"]["POSITION"])];
  EXPECT_EQ(pos["componentType"], 5126);  // FLOAT
  const auto& e =
      g.json["bufferViews"][std::size_t(pos["bufferView"])]["extensions"]["EXT_meshopt_compression"];
  EXPECT_EQ(e["filter"], "EXPONENTIAL");
  const std::size_t count = e["count"];
  std::vector<float> d(count * 3);
  ASSERT_EQ(meshopt_decodeVertexBuffer(
                d.data(), count, 12,
                reinterpret_cast<const unsigned char*>(g.bin.data()) + std::size_t(e["byteOffset"]),
                e["byteLength"]),
            0);
  meshopt_decodeFilterExp(d.data(), count, 12);
  const Primitive& in = s.meshes[0].primitives[0];
  double worst = 0;
  for (std::size_t i = 0; i < count; ++i) {
    double e2 = 0;
    for (std::size_t c = 0; c < 3; ++c) e2 += std::pow(double(d[i * 3 + c]) - in.positions[i * 3 + c], 2);
    worst = std::max(worst, std::sqrt(e2));
  }
  EXPECT_LE(worst, 0.002);
  EXPECT_GT(worst, 0.0002);              // really reduced, not exact
  for (std::size_t c = 0; c < 3; ++c) {  // min/max are the decoded bounds
    float lo = 1e9f;
    for (std::size_t i = 0; i < count; ++i) lo = std::min(lo, d[i * 3 + c]);
    EXPECT_EQ(float(pos["min"][c]), lo);
  }
  test::TempDir dir;
  test::write_file(dir / "e.glb", bytes);
  SYLVA_EXPECT_VALID_GLTF(dir / "e.glb");
  o.quantize.float_position_error = {};
  EXPECT_LT(bytes.size(), encode(s, o).size());
}

}  // namespace
}  // namespace sylva::gltf
