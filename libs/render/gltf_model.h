// Private: a parsed glTF (tinygltf::Model) and the file it came from, for the glTF loader
// (gltf_scene.cpp, gltf_materials.h, gltf_draco.h): checked reads of its accessors and buffer
// views, and the loader's one-line errors.
//
// tinygltf comes from Debian's shared library (TinyGLTF::TinyGLTF), which already contains the
// implementation: no translation unit here defines TINYGLTF_IMPLEMENTATION, so other sylva
// libraries can link the same library without duplicate symbols.
#pragma once

#include <tiny_gltf.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace sylva::render::detail {

// The glTF extensions the loader reads.
inline constexpr const char* kDraco = "KHR_draco_mesh_compression";
inline constexpr const char* kInstancing = "EXT_mesh_gpu_instancing";
inline constexpr const char* kUnlit = "KHR_materials_unlit";
inline constexpr const char* kTextureTransform = "KHR_texture_transform";

// Values of one attribute, `components` floats per element (count * components values).
struct AttributeData {
  int components = 0;
  std::size_t count = 0;
  std::vector<float> values;
};

// The most elements an accessor may declare unless the caller sets its own limit: 2^28, past
// any model the renderer draws. Checked before anything is allocated for the accessor.
inline constexpr std::size_t kMaxAccessorCount = std::size_t(1) << 28;

// `what` in the functions below names the reader of the data for messages ("mesh 3 'twigs'
// primitive 0 attribute NORMAL"); every failure throws SceneLoadError("<file>: error: <what>: ...").
class GltfModel {
 public:
  // `model` must outlive this. `max_count`: the most elements read_accessor and read_indices
  // accept from one accessor (a larger count fails before anything is allocated).
  GltfModel(const tinygltf::Model& model, std::string file, std::size_t max_count = kMaxAccessorCount)
      : m_(model), file_(std::move(file)), max_count_(max_count) {}

  const tinygltf::Model& model() const { return m_; }
  const std::string& file() const { return file_; }
  // Throws SceneLoadError("<file>: error: <why>").
  [[noreturn]] void fail(const std::string& why) const;

  const tinygltf::BufferView& buffer_view(int view, const std::string& what) const;
  // The bytes of `count` elements of `elem_size` bytes, `stride` apart, from `offset` in the
  // buffer view, once checked to lie inside it (and the view inside its buffer).
  const unsigned char* view_data(int view, std::size_t offset, std::size_t count, std::size_t stride,
                                 std::size_t elem_size, const std::string& what) const;
  // Accessor `index` as floats (normalised integers mapped to [0, 1] or [-1, 1]), sparse
  // values applied.
  AttributeData read_accessor(int index, const std::string& what) const;
  // Accessor `index` (which must exist) as indices: unsigned byte, short or int scalars, read as
  // integers.
  std::vector<std::uint32_t> read_indices(int index, const std::string& what) const;

 private:
  // Accessor `index` once its count is within max_count_.
  const tinygltf::Accessor& accessor(int index, const std::string& what) const;

  const tinygltf::Model& m_;
  std::string file_;
  std::size_t max_count_;
};

// A glTF URI percent-decoded ("my%20bark.png" -> "my bark.png").
std::string decode_uri(const std::string& uri);

}  // namespace sylva::render::detail
