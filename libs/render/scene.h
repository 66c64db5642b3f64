// What the renderer draws: a plain-data scene of meshes, materials and textures, already
// flattened to world space (every mesh carries the world matrices it is drawn with).
//
// Scenes normally come from load_gltf_scene() (gltf_scene.h), but they are ordinary structs,
// so a stage (the impostor baker, a test) can build one in code. Units are metres, Y up,
// right-handed, as in glTF.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace sylva::render {

using Vec2 = Eigen::Vector2f;
using Vec3 = Eigen::Vector3f;
using Vec4 = Eigen::Vector4f;
using Mat4 = Eigen::Matrix4f;  // column-major, acts on column vectors: p' = M * p

// Axis-aligned box; default-constructed it is empty (min > max) and extend() grows it.
struct Bounds {
  Vec3 min = Vec3::Constant(std::numeric_limits<float>::infinity());
  Vec3 max = Vec3::Constant(-std::numeric_limits<float>::infinity());

  bool empty() const { return !(min.array() <= max.array()).all(); }
  void extend(const Vec3& p);
  void extend(const Bounds& b);
  Vec3 center() const { return (min + max) * 0.5f; }
  float radius() const { return empty() ? 0.f : (max - min).norm() * 0.5f; }  // half diagonal
  Bounds transformed(const Mat4& m) const;  // bounds of the 8 transformed corners
};

enum class AlphaMode { kOpaque, kMask, kBlend };  // glTF material.alphaMode
enum class Wrap { kRepeat, kClampToEdge, kMirroredRepeat };
enum class Filter { kNearest, kLinear };

// A base-colour texture: 8-bit RGBA pixels, sRGB-encoded colour, straight alpha, top row first
// (glTF's uv (0,0) is the top-left corner of the image).
struct Texture {
  std::string name;  // for messages
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgba;  // width * height * 4
  Wrap wrap_s = Wrap::kRepeat, wrap_t = Wrap::kRepeat;
  Filter mag_filter = Filter::kLinear;
  Filter min_filter = Filter::kLinear;
  bool mipmaps = true;  // trilinear minification when min_filter is kLinear
};

struct Material {
  std::string name;
  Vec4 base_color = Vec4::Ones();  // linear RGBA factor (glTF baseColorFactor)
  int base_color_texture = -1;     // index into Scene::textures, -1 = none
  AlphaMode alpha_mode = AlphaMode::kOpaque;
  float alpha_cutoff = 0.5f;  // kMask: fragments with alpha < cutoff are discarded
  bool double_sided = false;  // no back-face culling; back faces use the reversed normal (glTF)
  bool unlit = false;         // KHR_materials_unlit: colour = base colour, no lighting
};

enum class Topology { kTriangles, kLines, kPoints };

// One draw's worth of geometry. Strips, fans and loops are already expanded to lists.
struct Primitive {
  Topology topology = Topology::kTriangles;
  std::vector<Vec3> positions;         // required
  std::vector<Vec3> normals;           // empty or one per position; empty triangles get flat normals
  std::vector<Vec2> texcoords;         // empty or one per position (the set the material samples)
  std::vector<Vec4> colors;            // empty or one per position (COLOR_0), linear RGBA
  std::vector<float> sizes;            // POINTS only: empty or one per position; point diameter in
                                       // metres in the mesh's local space (glTF attribute _SIZE)
  std::vector<std::uint32_t> indices;  // 3 per triangle, 2 per line, 1 per point; all < size
  int material = -1;                   // index into Scene::materials, -1 = default material
  // LINES only: empty, or one per position: the line stands for that many (1..3) coincident
  // copies drawn one over the other; its alpha a is drawn as 1 - (1 - a)^copies, what the copies'
  // "over"s composite to (merge_line_copies, line_merge.h).
  std::vector<float> copies;

  Bounds bounds() const;              // of positions, local space
  std::size_t element_count() const;  // triangles, lines or points
};

struct Mesh {
  std::string name;
  std::vector<Primitive> primitives;
  std::vector<Mat4> instances;  // world matrices; the mesh is drawn once per entry
  // Optional name of the geometry, for renderers that keep it uploaded between calls (a forest's
  // species levels, drawn by every view). Two meshes name the same geometry when their pointers
  // hold the same address and share ownership; while its owner lives, every mesh naming it has
  // the same primitives' vertex arrays and indices (materials and instances may differ). Null:
  // the primitives are uploaded for each call.
  std::shared_ptr<const void> shared_geometry;
};

// Where a (hemi-)octahedral impostor's frames are and what they span: the reference shader's
// uniforms (shaders/octahedral_impostor.*, docs/stages/impostor.md "The reference shader"); the
// fields follow impostor.json (impostor_geometry() in impostor_atlas.h reads them from it).
struct ImpostorGeometry {
  int frames_per_side = 16;    // N: frames per atlas side
  bool hemi = true;            // upper hemisphere only
  Vec3 center = Vec3::Zero();  // sphere centre, object space
  float radius = 1;            // sphere radius R
  float half_extent = 1;       // frame half extent W
  int frame_px = 256;          // texels per frame side
  int padding_px = 16;         // transparent texels round the sphere's disc in every frame
  int mip_levels = 4;          // GL_TEXTURE_MAX_LEVEL of both maps
};

// A (hemi-)octahedral impostor as the reference shader draws it: both maps atlas_px x atlas_px
// RGBA8, top row first, ALREADY premultiplied by coverage (premultiply_impostor_maps() in
// impostor_atlas.h turns impostor.json's straight PNGs into them).
struct ImpostorAtlas {
  std::string name;                        // for messages
  int atlas_px = 0;                        // frames_per_side * frame_px
  std::vector<std::uint8_t> color;         // sRGB(linear rgb * a), a = coverage
  std::vector<std::uint8_t> normal_depth;  // rgb = (normal * 0.5 + 0.5) * a, a = depth
  ImpostorGeometry geometry;
};

// Instances of one impostor (object -> world: rotation, translation, uniform scale). The atlas
// is shared, not copied, between the scenes that draw it.
struct ImpostorSet {
  std::shared_ptr<const ImpostorAtlas> atlas;
  std::vector<Mat4> instances;
  int parallax_steps = 16;  // ray-march steps per frame (0 = flat frames)
};

struct Scene {
  std::string source;  // file the scene came from (for messages), may be empty
  // What the renderer ignored, one line each ("uses glTF extension 'KHR_texture_transform',
  // which sylva's renderer ignores: ..."): the picture may differ from other viewers'.
  std::vector<std::string> warnings;
  std::vector<Texture> textures;
  std::vector<Material> materials;
  std::vector<Mesh> meshes;
  // Drawn after the opaque and masked primitives (depth test on, no depth write, every instance
  // of every set far to near by its sphere centre, blended with alpha = coverage), before the
  // BLEND primitives.
  std::vector<ImpostorSet> impostors;

  Bounds bounds() const;  // world-space box over every instance of every primitive and impostor
  // Element counts over all instances (for logs and benchmarks).
  std::size_t triangle_count() const;
  std::size_t line_count() const;
  std::size_t point_count() const;
};

}  // namespace sylva::render
