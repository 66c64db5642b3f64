// The glTF writer: every file it produces passes the Khronos validator, reads back through
// tinygltf with the values that went in, is byte-identical when written twice, and Draco
// round-trips within the quantisation error.
#include "libs/gltf/writer.h"

#include <draco/compression/decode.h>
#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "libs/gltf/scene.h"
#include "libs/gltf/testing/sample_geometry.h"
#include "tests/support/gltf_fixtures.h"
#include "tests/support/gltf_validator.h"
#include "tests/support/test_support.h"

namespace sylva::gltf {
namespace {

using test::Glb;
using test::parse_glb;

using testing::make_node;

WriteOptions gltf_text() {
  WriteOptions o;
  o.format = FileFormat::kGltf;
  return o;
}

// An n x n grid of quads in the XZ plane (y = a gentle bump), facing +Y, with every attribute.
Primitive grid(int n) {
  Primitive p;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const float x = static_cast<float>(i) / n, z = static_cast<float>(j) / n;
      p.positions.insert(p.positions.end(), {x, 0.1f * std::sin(3 * x) * std::cos(2 * z), z});
      p.normals.insert(p.normals.end(), {0, 1, 0});
      p.tangents.insert(p.tangents.end(), {1, 0, 0, 1});
      p.texcoords.insert(p.texcoords.end(), {x, z});
      p.colors.insert(p.colors.end(), {x, z, 0.5f, 1});
    }
  const auto at = [n](int i, int j) { return static_cast<std::uint32_t>(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      // Counter-clockwise seen from +Y: (i,j) -> (i,j+1) -> (i+1,j+1).
      p.indices.insert(p.indices.end(), {at(i, j), at(i, j + 1), at(i + 1, j + 1)});
      p.indices.insert(p.indices.end(), {at(i, j), at(i + 1, j + 1), at(i + 1, j)});
    }
  return p;
}

Scene textured_scene() {
  Scene s;
  s.images.push_back({"bark.png", "image/png", test::tiny_png(), ""});
  Material m;
  m.name = "bark";
  m.base_color_texture.image = 0;
  m.normal_texture.image = 0;  // a normal map: its primitive keeps its tangents
  s.materials.push_back(m);
  Material leaf;
  leaf.name = "leaf";
  leaf.base_color = {0.2f, 0.5f, 0.1f, 1};
  leaf.base_color_texture = {0, Wrap::kClampToEdge, Wrap::kClampToEdge};
  leaf.alpha_mode = AlphaMode::kMask;
  leaf.alpha_cutoff = 0.4f;
  leaf.double_sided = true;
  s.materials.push_back(leaf);
  Mesh mesh;
  mesh.name = "tree";
  Primitive a = grid(4);
  a.material = 0;
  a.extras = {{"part", "bark"}};
  Primitive b = grid(2);
  b.material = 1;
  mesh.primitives = {a, b};
  s.meshes.push_back(mesh);
  Node n;
  n.name = "tree";
  n.mesh = 0;
  n.translation = {1, 0, 0};
  s.nodes.push_back(n);
  s.roots = {0};
  s.extras = {{"sylva", {{"stage", "test"}, {"stage_version", 1}, {"statistics", {{"quads", 16}}}}}};
  return s;
}

tinygltf::Model load(const std::string& bytes, bool glb) {
  tinygltf::TinyGLTF loader;
  tinygltf::Model model;
  std::string err, warn;
  const bool ok = glb ? loader.LoadBinaryFromMemory(&model, &err, &warn,
                                                    reinterpret_cast<const unsigned char*>(bytes.data()),
                                                    static_cast<unsigned>(bytes.size()))
                      : loader.LoadASCIIFromString(&model, &err, &warn, bytes.data(),
                                                   static_cast<unsigned>(bytes.size()), "");
  EXPECT_TRUE(ok) << err;
  return model;
}

template <typename T>
std::vector<T> read_accessor(const tinygltf::Model& m, int index) {
  const tinygltf::Accessor& a = m.accessors[static_cast<std::size_t>(index)];
  const tinygltf::BufferView& v = m.bufferViews[static_cast<std::size_t>(a.bufferView)];
  const auto& data = m.buffers[static_cast<std::size_t>(v.buffer)].data;
  const std::size_t comps =
      static_cast<std::size_t>(tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(a.type)));
  std::vector<T> out(a.count * comps);
  std::memcpy(out.data(), data.data() + v.byteOffset + a.byteOffset, out.size() * sizeof(T));
  return out;
}

std::filesystem::path write(const test::TempDir& dir, const std::string& name, const std::string& bytes) {
  const auto path = dir / name;
  test::write_file(path, bytes);
  return path;
}

// A GLB with two textured primitives, a MASK material and extras: valid, and everything reads back.
TEST(GltfWriter, GlbRoundTripsThroughTinygltfAndValidates) {
  const Scene s = textured_scene();
  const std::string bytes = encode(s);
  test::TempDir dir;
  SYLVA_EXPECT_VALID_GLTF(write(dir, "scene.glb", bytes));

  const tinygltf::Model m = load(bytes, true);
  ASSERT_EQ(m.meshes.size(), 1u);
  ASSERT_EQ(m.meshes[0].primitives.size(), 2u);
  const tinygltf::Primitive& p = m.meshes[0].primitives[0];
  EXPECT_EQ(read_accessor<float>(m, p.attributes.at("POSITION")), s.meshes[0].primitives[0].positions);
  EXPECT_EQ(read_accessor<float>(m, p.attributes.at("NORMAL")), s.meshes[0].primitives[0].normals);
  EXPECT_EQ(read_accessor<float>(m, p.attributes.at("TANGENT")), s.meshes[0].primitives[0].tangents);
  // The leaf material has no normal map: its primitive's tangents are not written.
  EXPECT_EQ(m.meshes[0].primitives[1].attributes.count("TANGENT"), 0u);
  EXPECT_EQ(m.materials[0].normalTexture.index, m.materials[0].pbrMetallicRoughness.baseColorTexture.index);
  EXPECT_EQ(read_accessor<float>(m, p.attributes.at("TEXCOORD_0")), s.meshes[0].primitives[0].texcoords);
  EXPECT_EQ(read_accessor<float>(m, p.attributes.at("COLOR_0")), s.meshes[0].primitives[0].colors);
  const std::vector<std::uint16_t> idx = read_accessor<std::uint16_t>(m, p.indices);
  EXPECT_TRUE(std::equal(idx.begin(), idx.end(), s.meshes[0].primitives[0].indices.begin(),
                         s.meshes[0].primitives[0].indices.end()));
  EXPECT_EQ(m.accessors[static_cast<std::size_t>(p.attributes.at("POSITION"))].minValues.size(), 3u);

  ASSERT_EQ(m.materials.size(), 2u);
  EXPECT_EQ(m.materials[1].alphaMode, "MASK");
  EXPECT_DOUBLE_EQ(m.materials[1].alphaCutoff, 0.4f);
  EXPECT_TRUE(m.materials[1].doubleSided);
  EXPECT_EQ(m.materials[0].alphaMode, "OPAQUE");
  // One image, one texture per distinct sampler (repeat for bark, clamp for leaves).
  EXPECT_EQ(m.images.size(), 1u);
  EXPECT_EQ(m.samplers.size(), 2u);
  EXPECT_EQ(m.textures.size(), 2u);
  // The image is embedded byte for byte.
  const tinygltf::BufferView& iv = m.bufferViews[static_cast<std::size_t>(m.images[0].bufferView)];
  EXPECT_EQ(
      std::string(reinterpret_cast<const char*>(m.buffers[0].data.data() + iv.byteOffset), iv.byteLength),
      test::tiny_png());
  EXPECT_EQ(m.asset.extras.Get("sylva").Get("stage").Get<std::string>(), "test");
  EXPECT_EQ(m.asset.extras.Get("sylva").Get("statistics").Get("quads").Get<int>(), 16);
  EXPECT_EQ(m.meshes[0].primitives[0].extras.Get("part").Get<std::string>(), "bark");
  ASSERT_EQ(m.nodes.size(), 1u);
  EXPECT_EQ(m.nodes[0].translation, (std::vector<double>{1, 0, 0}));
}

// The .gltf form is one self-contained file (data URI) and validates too.
TEST(GltfWriter, GltfTextFormIsSelfContained) {
  const Scene s = textured_scene();
  const std::string text = encode(s, gltf_text());
  ASSERT_EQ(text.front(), '{');
  EXPECT_NE(text.find("data:application/octet-stream;base64,"), std::string::npos);
  test::TempDir dir;
  SYLVA_EXPECT_VALID_GLTF(write(dir, "scene.gltf", text));
  const tinygltf::Model m = load(text, false);
  EXPECT_EQ(read_accessor<float>(m, m.meshes[0].primitives[1].attributes.at("POSITION")),
            s.meshes[0].primitives[1].positions);
}

// Materials no primitive uses and images no written material uses are left out; indices are
// remapped. (The oak's LOD chain carried 12 unused materials and the pine's an unused image.)
TEST(GltfWriter, UnusedMaterialsAndImagesAreNotWritten) {
  Scene s = textured_scene();
  s.images.insert(s.images.begin(), {"unused.png", "image/png", test::tiny_png(), ""});
  for (Material& m : s.materials) {
    m.base_color_texture.image = 1;
    m.normal_texture.image = -1;
  }
  Material unused;
  unused.name = "unused";
  s.materials.insert(s.materials.begin(), unused);
  for (Primitive& p : s.meshes[0].primitives) ++p.material;
  s.meshes[0].primitives[1].material = 2;
  const Glb g = parse_glb(encode(s));
  ASSERT_EQ(g.json["materials"].size(), 2u);
  EXPECT_EQ(g.json["materials"][0]["name"], "bark");
  EXPECT_EQ(g.json["meshes"][0]["primitives"][0]["material"], 0);
  EXPECT_EQ(g.json["meshes"][0]["primitives"][1]["material"], 1);
  ASSERT_EQ(g.json["images"].size(), 1u);
  EXPECT_EQ(g.json["images"][0]["name"], "bark.png");
  EXPECT_EQ(g.json["textures"][0]["source"], 0);
  test::TempDir dir;
  SYLVA_EXPECT_VALID_GLTF(write(dir, "pruned.glb", encode(s)));
}

// External .gltf: buffers and images are files beside the JSON; two scenes that hold the same
// primitives in a buffer of the same name write the same .bin bytes, so one file can serve both
// (the lod stage's lod.gltf reads its levels' lod<i>.bin); a primitive can go to a second buffer.
TEST(GltfWriter, ExternalBuffersAndImagesAreSharedFiles) {
  Scene one = textured_scene();
  one.images[0].uri = "bark.png";
  one.buffer_uris = {"tree.bin"};
  const EncodedFiles a = encode_external(one);
  ASSERT_EQ(a.resources.size(), 2u);
  EXPECT_EQ(a.resources[0].name, "tree.bin");
  EXPECT_EQ(a.resources[1].name, "bark.png");
  EXPECT_EQ(a.resources[1].bytes, test::tiny_png());
  const nlohmann::json ja = nlohmann::json::parse(a.gltf);
  EXPECT_EQ(ja["buffers"],
            nlohmann::json::parse(R"([{"byteLength": )" + std::to_string(a.resources[0].bytes.size()) +
                                  R"(, "uri": "tree.bin"}])"));
  EXPECT_EQ(ja["images"][0]["uri"], "bark.png");
  EXPECT_FALSE(ja["images"][0].contains("bufferView"));
  EXPECT_EQ(a.gltf.find("data:"), std::string::npos);

  // Two copies of the mesh, the second in its own buffer "copy.bin", the first in "tree.bin".
  Scene two = one;
  two.buffer_uris = {"tree.bin", "copy.bin"};
  two.meshes.push_back(one.meshes[0]);
  two.meshes[1].buffer = 1;
  two.nodes.push_back(make_node("copy", 1));
  two.roots = {0, 1};
  const EncodedFiles b = encode_external(two);
  ASSERT_EQ(b.resources.size(), 3u);
  EXPECT_EQ(b.resources[0].bytes, a.resources[0].bytes);  // the same tree.bin
  EXPECT_EQ(b.resources[1].name, "copy.bin");
  EXPECT_EQ(b.resources[1].bytes, a.resources[0].bytes);  // same primitives, same layout

  // A primitive moved to another buffer: the mesh's own buffer keeps the rest as a prefix.
  Scene split = one;
  split.buffer_uris = {"tree.bin", "extra.bin"};
  split.meshes[0].primitives[1].buffer = 1;
  const EncodedFiles c = encode_external(split);
  ASSERT_EQ(c.resources.size(), 3u);
  EXPECT_LT(c.resources[0].bytes.size(), a.resources[0].bytes.size());
  EXPECT_EQ(a.resources[0].bytes.compare(0, c.resources[0].bytes.size(), c.resources[0].bytes), 0);
  // ... and can declare the longer file it shares with a.gltf.
  split.buffer_byte_lengths = {a.resources[0].bytes.size()};
  const EncodedFiles c_long = encode_external(split);
  EXPECT_EQ(nlohmann::json::parse(c_long.gltf)["buffers"][0]["byteLength"], a.resources[0].bytes.size());
  EXPECT_EQ(c_long.resources[0].bytes, c.resources[0].bytes);
  split.buffer_byte_lengths = {4};
  EXPECT_THROW(encode_external(split), GltfError);
  split.buffer_byte_lengths.clear();

  test::TempDir dir;
  for (const EncodedFiles* f : {&a, &b, &c}) {
    const std::string name = f == &a ? "a.gltf" : f == &b ? "b.gltf" : "c.gltf";
    for (const EncodedFile& r : f->resources)
      write(dir, r.name == "tree.bin" && f == &c ? "tree.bin" : r.name, r.bytes);
    SYLVA_EXPECT_VALID_GLTF(write(dir, name, f->gltf));
  }
  // c.gltf reads the shorter tree.bin it wrote; a.gltf and b.gltf a longer file of the same name
  // would be wrong, so validate them again with their own bytes in place.
  write(dir, "tree.bin", a.resources[0].bytes);
  SYLVA_EXPECT_VALID_GLTF(write(dir, "c_long.gltf", c_long.gltf));
  SYLVA_EXPECT_VALID_GLTF(dir / "a.gltf");
  SYLVA_EXPECT_VALID_GLTF(dir / "b.gltf");
  // Deterministic text.
  EXPECT_EQ(encode_external(two).gltf, b.gltf);
}

// External output refuses what it cannot write: no buffer names, an empty buffer, bad names.
TEST(GltfWriter, ExternalOutputRefusesBadBuffers) {
  Scene s = textured_scene();
  EXPECT_THROW(encode_external(s), GltfError);  // no buffer_uris
  s.buffer_uris = {"tree.bin", "empty.bin"};
  try {
    encode_external(s);
    ADD_FAILURE() << "an empty buffer was accepted";
  } catch (const GltfError& e) {
    EXPECT_STREQ(e.what(), "invalid glTF scene: buffer_uris[1] ('empty.bin') holds no data");
  }
  s.buffer_uris = {"../tree.bin"};
  EXPECT_EQ(validate_scene(s).at(0), "buffer_uris[0]: '../tree.bin' is not a plain file name");
  s.buffer_uris = {"tree.bin"};
  s.meshes[0].buffer = 3;
  EXPECT_EQ(validate_scene(s).at(0), "meshes[0]: buffer 3 is not in buffer_uris");
  WriteOptions external;
  external.format = FileFormat::kGltfExternal;
  EXPECT_THROW(encode(textured_scene(), external), GltfError);
}

// Same scene, same bytes; no clock, no addresses.
TEST(GltfWriter, BytesAreDeterministic) {
  EXPECT_EQ(encode(textured_scene()), encode(textured_scene()));
  WriteOptions d;
  d.draco.enabled = true;
  EXPECT_EQ(encode(textured_scene(), d), encode(textured_scene(), d));
}

// LINES and POINTS (with a custom _SIZE attribute) and non-indexed triangles are valid.
TEST(GltfWriter, LinesPointsAndNonIndexedPrimitivesValidate) {
  Scene s;
  Mesh mesh;
  Primitive lines;
  lines.mode = PrimitiveMode::kLines;
  lines.positions = {0, 0, 0, 0, 1, 0, 0, 1, 0, 0.5f, 1.5f, 0};
  lines.colors = {0.4f, 0.3f, 0.2f, 1, 0.4f, 0.3f, 0.2f, 1, 0.4f, 0.3f, 0.2f, 0.5f, 0.4f, 0.3f, 0.2f, 0.5f};
  lines.indices = {0, 1, 2, 3};
  Primitive points;
  points.mode = PrimitiveMode::kPoints;
  points.positions = {0, 2, 0, 1, 2, 0, 0, 2, 1};
  points.custom.push_back({"_SIZE", 1, {0.1f, 0.2f, 0.3f}});
  Primitive tris;
  tris.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  mesh.primitives = {lines, points, tris};
  s.meshes.push_back(mesh);
  s.nodes.push_back(make_node("n", 0));
  s.roots = {0};
  WriteOptions d;
  d.draco.enabled = true;  // applies to the triangles only
  test::TempDir dir;
  const auto a = write(dir, "plain.glb", encode(s));
  const auto b = write(dir, "draco.glb", encode(s, d));
  for (const auto& r : test::validate_gltf(std::vector<std::filesystem::path>{a, b})) {
    if (r.skipped) GTEST_SKIP() << r.skip_reason;
    EXPECT_TRUE(r.ok()) << r.tool_error << r.report;
  }
  const nlohmann::json j = parse_glb(encode(s, d)).json;
  const auto& prims = j["meshes"][0]["primitives"];
  EXPECT_EQ(prims[0]["mode"], 1);
  EXPECT_FALSE(prims[0].contains("extensions"));
  EXPECT_TRUE(prims[1]["attributes"].contains("_SIZE"));
  EXPECT_TRUE(prims[2]["extensions"].contains("KHR_draco_mesh_compression"));
}

// Draco: the file validates, the extension is required, and the decoded positions, normals and
// uvs lie within the quantisation error of the input.
TEST(GltfWriter, DracoRoundTripWithinQuantisationError) {
  Scene s;
  Mesh mesh;
  Primitive p = grid(24);
  mesh.primitives.push_back(p);
  s.meshes.push_back(mesh);
  s.nodes.push_back(make_node("grid", 0));
  s.roots = {0};
  WriteOptions o;
  o.draco.enabled = true;
  o.draco.position_bits = 11;
  o.draco.texcoord_bits = 10;
  const std::string bytes = encode(s, o);
  EXPECT_LT(bytes.size(), encode(s).size());
  test::TempDir dir;
  SYLVA_EXPECT_VALID_GLTF(write(dir, "draco.glb", bytes));

  const Glb glb = parse_glb(bytes);
  const nlohmann::json& j = glb.json;
  ASSERT_EQ(j["extensionsRequired"], nlohmann::json::array({"KHR_draco_mesh_compression"}));
  const nlohmann::json& gp = j["meshes"][0]["primitives"][0];
  const nlohmann::json& ext = gp["extensions"]["KHR_draco_mesh_compression"];
  const nlohmann::json& view = j["bufferViews"][ext["bufferView"].get<std::size_t>()];
  draco::DecoderBuffer buffer;
  buffer.Init(glb.bin.data() + view.value("byteOffset", std::size_t{0}),
              view["byteLength"].get<std::size_t>());
  draco::Decoder decoder;
  auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
  ASSERT_TRUE(decoded.ok()) << decoded.status().error_msg();
  const std::unique_ptr<draco::Mesh> dm = std::move(decoded).value();
  // The accessors declare exactly what the decoder returns.
  EXPECT_EQ(j["accessors"][gp["attributes"]["POSITION"].get<std::size_t>()]["count"], dm->num_points());
  EXPECT_EQ(j["accessors"][gp["indices"].get<std::size_t>()]["count"], dm->num_faces() * 3);
  EXPECT_EQ(dm->num_faces() * 3, p.indices.size());

  // Quantisation error bound: Draco quantises every component on one grid whose extent is the
  // largest of the bounding box's sides: step = extent / (2^bits - 1), error <= step / 2.
  const double pos_step = 1.0 / ((1 << o.draco.position_bits) - 1);
  const double uv_step = 1.0 / ((1 << o.draco.texcoord_bits) - 1);
  const draco::PointAttribute* pos =
      dm->GetAttributeByUniqueId(ext["attributes"]["POSITION"].get<std::uint32_t>());
  const draco::PointAttribute* uv =
      dm->GetAttributeByUniqueId(ext["attributes"]["TEXCOORD_0"].get<std::uint32_t>());
  const draco::PointAttribute* nrm =
      dm->GetAttributeByUniqueId(ext["attributes"]["NORMAL"].get<std::uint32_t>());
  ASSERT_TRUE(pos && uv && nrm);
  // Points may be reordered: match each decoded point to the nearest input vertex.
  double worst_pos = 0, worst_uv = 0, worst_normal_dot = 1;
  for (draco::PointIndex i(0); i < dm->num_points(); ++i) {
    std::array<float, 3> q{};
    std::array<float, 2> t{};
    std::array<float, 3> nn{};
    pos->GetMappedValue(i, q.data());
    uv->GetMappedValue(i, t.data());
    nrm->GetMappedValue(i, nn.data());
    double best = 1e9;
    std::size_t best_k = 0;
    for (std::size_t k = 0; k < p.vertex_count(); ++k) {
      double d = 0;
      for (int c = 0; c < 3; ++c)
        d = std::max(d, std::abs(double(q[static_cast<std::size_t>(c)]) -
                                 p.positions[3 * k + static_cast<std::size_t>(c)]));
      if (d < best) best = d, best_k = k;
    }
    worst_pos = std::max(worst_pos, best);
    for (int c = 0; c < 2; ++c)
      worst_uv = std::max(worst_uv, std::abs(double(t[static_cast<std::size_t>(c)]) -
                                             p.texcoords[2 * best_k + static_cast<std::size_t>(c)]));
    worst_normal_dot = std::min(worst_normal_dot, double(nn[1]));
  }
  EXPECT_LE(worst_pos, pos_step / 2 * 1.0001);
  EXPECT_LE(worst_uv, uv_step / 2 * 1.0001);
  EXPECT_GT(worst_normal_dot, 0.999);
}

// EXT_mesh_gpu_instancing nodes validate and carry one entry per instance.
TEST(GltfWriter, InstancingValidates) {
  Scene s;
  Mesh mesh;
  mesh.primitives.push_back(grid(1));
  s.meshes.push_back(mesh);
  Node n;
  n.name = "forest";
  n.mesh = 0;
  n.instances.translations = {0, 0, 0, 5, 0, 0, 0, 0, 5};
  n.instances.rotations = {0, 0, 0, 1, 0, 0.7071068f, 0, 0.7071068f, 0, 1, 0, 0};
  s.nodes.push_back(n);
  s.roots = {0};
  test::TempDir dir;
  SYLVA_EXPECT_VALID_GLTF(write(dir, "inst.glb", encode(s)));
  const nlohmann::json j = parse_glb(encode(s)).json;
  EXPECT_EQ(j["extensionsRequired"], nlohmann::json::array({"EXT_mesh_gpu_instancing"}));
  EXPECT_EQ(j["accessors"][j["nodes"][0]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"]["TRANSLATION"]
                               .get<std::size_t>()]["count"],
            3);
}

// Node extensions (MSFT_lod here) are written as given and listed in extensionsUsed.
TEST(GltfWriter, NodeExtensionsAreWrittenAndListed) {
  Scene s;
  Mesh mesh;
  mesh.primitives.push_back(grid(1));
  s.meshes.push_back(mesh);
  Node lod0 = make_node("lod0", 0);
  lod0.extensions = {{"MSFT_lod", {{"ids", {1}}}}};
  lod0.extras = {{"MSFT_screencoverage", {0.5, 0.0}}};
  s.nodes = {lod0, make_node("lod1", 0)};
  s.roots = {0};
  test::TempDir dir;
  SYLVA_EXPECT_VALID_GLTF(write(dir, "lod.glb", encode(s)));
  const nlohmann::json j = parse_glb(encode(s)).json;
  EXPECT_EQ(j["nodes"][0]["extensions"]["MSFT_lod"]["ids"], nlohmann::json::array({1}));
  EXPECT_EQ(j["extensionsUsed"], nlohmann::json::array({"MSFT_lod"}));
  EXPECT_FALSE(j.contains("extensionsRequired"));
}

// A scene that breaks the contract is refused with the element named, before anything is written.
TEST(GltfWriter, InvalidSceneIsRefusedWithTheElementNamed) {
  Scene s = textured_scene();
  s.meshes[0].primitives[1].normals.pop_back();
  try {
    encode(s);
    FAIL() << "expected GltfError";
  } catch (const GltfError& e) {
    EXPECT_STREQ(
        e.what(),
        "invalid glTF scene: meshes[0].primitives[1]: normals has 26 values, expected 3 per vertex (27)");
  }
}

// An empty scene (no meshes) is still a valid file.
TEST(GltfWriter, EmptySceneIsValid) {
  Scene s;
  s.nodes.push_back(make_node("empty"));
  s.roots = {0};
  test::TempDir dir;
  SYLVA_EXPECT_VALID_GLTF(write(dir, "empty.glb", encode(s)));
}

}  // namespace
}  // namespace sylva::gltf
