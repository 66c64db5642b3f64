// Deterministic mutation fuzzers for the two parsers that read outside data (camera sets and
// glTF files): thousands of byte-level mutations of valid inputs must each load or fail with
// the library's own error type, never crash, hang or throw anything else; scenes that load must
// render without an OpenGL error.
#include <gtest/gtest.h>

#include <fstream>
#include <random>
#include <regex>

#include "libs/render/camera.h"
#include "libs/render/gltf_scene.h"
#include "libs/render/renderer.h"
#include "libs/render/testing/gltf_builder.h"
#include "tests/support/test_support.h"

namespace sylva::render {
namespace {

std::string mutate(std::string text, std::mt19937& rng, const std::string& alphabet) {
  const int edits = 1 + int(rng() % 4);
  for (int e = 0; e < edits && !text.empty(); ++e) {
    const std::size_t pos = rng() % text.size();
    switch (rng() % 3) {
      case 0:
        text[pos] = alphabet[rng() % alphabet.size()];
        break;
      case 1:
        text.erase(pos, 1 + rng() % 8);
        break;
      default:
        text.insert(pos, 1, alphabet[rng() % alphabet.size()]);
    }
  }
  return text;
}

TEST(FuzzCameraSet, MutatedSetsNeverCrash) {
  const std::string seed = test::read_file("configs/cameras/verify.yaml") +
                           "  - name: eye\n    eye: [1, 2, 3]\n    target: [0, 0, 0]\n    up: [0, 1, 0]\n";
  std::mt19937 rng(2026);
  const std::string alphabet = "{}[]:,'\"-\n #\t0123456789.e_abcxyz";
  const std::regex line("^cams\\.yaml(:[0-9]+:[0-9]+)?: error: .+$");
  int loaded = 0, rejected = 0;
  for (int i = 0; i < 3000; ++i) {
    const std::string text = mutate(seed, rng, alphabet);
    try {
      const CameraSet set = parse_camera_set(text, "cams.yaml");
      ++loaded;
      ASSERT_FALSE(set.views.empty()) << text;
      for (const CameraView& v : set.views) {
        const Camera c = resolve(v, Bounds(), float(set.width) / float(set.height));
        ASSERT_TRUE(c.view_matrix().allFinite()) << text;
        ASSERT_GT(c.z_far, c.z_near) << text;
      }
    } catch (const CameraSetError& e) {
      ++rejected;
      ASSERT_FALSE(e.errors().empty()) << text;
      for (const std::string& l : e.errors()) ASSERT_TRUE(std::regex_match(l, line)) << l << "\n" << text;
    }
  }
  EXPECT_GT(loaded, 100);
  EXPECT_GT(rejected, 100);
}

// A GLB with most of what the loader reads: textured masked material, blended lines, sized
// points, instancing, a Draco primitive.
std::string seed_glb(const test::TempDir& dir) {
  testing::GltfBuilder b;
  image::Image tex(2, 2, {10, 200, 30, 255});
  tex.set(1, 1, {0, 0, 0, 0});
  const int leaf =
      b.add_material({.texture = b.add_texture(tex), .alpha_mode = "MASK", .double_sided = true});
  const int line = b.add_material({.base_color = Vec4(0.4f, 0.3f, 0.2f, 0.5f), .alpha_mode = "BLEND"});
  testing::PrimitiveData lines;
  lines.mode = TINYGLTF_MODE_LINE_STRIP;
  lines.positions = {{0, 0, 0}, {0, 1, 0}, {0.3f, 1.5f, 0}};
  lines.material = line;
  testing::PrimitiveData pts;
  pts.mode = TINYGLTF_MODE_POINTS;
  pts.positions = {{0, 2, 0}, {0.1f, 2, 0}};
  pts.sizes = {0.1f, 0.2f};
  testing::PrimitiveData cube = testing::cube(0.5f, leaf);
  cube.draco = true;
  testing::NodeData n;
  n.mesh = b.add_mesh({testing::quad(1.f, leaf), lines, pts});
  n.instance_translations = {{0, 0, 0}, {2, 0, 0}};
  b.add_root(b.add_node(n));
  b.add_root(b.add_node({.mesh = b.add_mesh({cube}), .translation = Vec3(0, 0, 1)}));
  b.write_glb(dir / "seed.glb");
  return test::read_file(dir / "seed.glb");
}

TEST(FuzzGltf, MutatedFilesNeverCrash) {
  test::TempDir dir;
  const std::string seed = seed_glb(dir);
  ASSERT_NO_THROW(load_gltf_scene(dir / "seed.glb"));
  std::unique_ptr<Renderer> renderer;
  try {
    renderer = Renderer::create_headless();
  } catch (const RenderUnavailableError&) {
    // Loading is still fuzzed; rendering is covered where GL exists.
  }
  RenderOptions o;
  o.width = o.height = 32;
  o.msaa = 1;
  std::mt19937 rng(7);
  const std::string alphabet =
      std::string("{}[]:,\"0123456789-.e \n\x00\xff", 24) + "abcdefghijklmnopqrstuvwxyz_";
  const std::regex line("^.+: error: .+$");
  int loaded = 0, rejected = 0, rendered = 0;
  // The seed's JSON chunk and everything after it (the BIN chunk).
  auto le32 = [](const std::string& b, std::size_t at) {
    return std::uint32_t(std::uint8_t(b[at])) | std::uint32_t(std::uint8_t(b[at + 1])) << 8 |
           std::uint32_t(std::uint8_t(b[at + 2])) << 16 | std::uint32_t(std::uint8_t(b[at + 3])) << 24;
  };
  auto put32 = [](std::string& b, std::uint32_t v) {
    for (int k = 0; k < 4; ++k) b += char((v >> (8 * k)) & 0xff);
  };
  const std::size_t json_len = le32(seed, 12);
  const std::string json = seed.substr(20, json_len);
  const std::string rest = seed.substr(20 + json_len);
  for (int i = 0; i < 1500; ++i) {
    std::string bytes;
    switch (i % 3) {
      case 0: {  // mutate the JSON, keep the container valid
        std::string j = mutate(json, rng, alphabet);
        while (j.size() % 4) j += ' ';
        bytes = "glTF";
        put32(bytes, 2);
        put32(bytes, std::uint32_t(20 + j.size() + rest.size()));
        put32(bytes, std::uint32_t(j.size()));
        bytes += "JSON";
        bytes += j + rest;
        break;
      }
      case 1: {  // overwrite binary bytes (geometry, Draco stream, PNG) in place
        bytes = seed;
        const int edits = 1 + int(rng() % 8);
        for (int e = 0; e < edits; ++e) bytes[20 + json_len + rng() % rest.size()] = char(rng() & 0xff);
        break;
      }
      default:
        bytes = mutate(seed, rng, alphabet);
    }
    const auto path = dir / "m.glb";
    {
      std::ofstream f(path, std::ios::binary | std::ios::trunc);
      f.write(bytes.data(), std::streamsize(bytes.size()));
    }
    Scene s;
    try {
      s = load_gltf_scene(path);
      ++loaded;
    } catch (const SceneLoadError& e) {
      ++rejected;
      ASSERT_TRUE(std::regex_match(std::string(e.what()), line)) << e.what();
      continue;
    }
    if (renderer) {
      const Bounds b = s.bounds();
      CameraView v;
      v.placement = OrbitView{30, 20, 1.2f, 0};
      const Camera c = resolve(v, b, 1.f);
      try {
        renderer->render(s, c, o);
        ++rendered;
      } catch (const RenderError& e) {
        // Non-finite geometry can make a camera degenerate; anything else is a bug.
        ASSERT_TRUE(!c.view_matrix().allFinite() || !b.min.allFinite() || !b.max.allFinite()) << e.what();
      }
    }
  }
  EXPECT_GT(loaded, 100);
  EXPECT_GT(rejected, 100);
  std::cout << "loaded " << loaded << ", rejected " << rejected << ", rendered " << rendered << "\n";
}

}  // namespace
}  // namespace sylva::render
