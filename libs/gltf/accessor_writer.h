// Private to libs/gltf: the bytes of a model's buffers and the buffer views and accessors over
// them (writer.h, "Layout"). Each view starts 4-byte aligned in the buffer it goes to.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace tinygltf {
class Model;
}

namespace sylva::gltf::detail {

class AccessorWriter {
 public:
  // Views and accessors are appended to `model` (not owned); `buffers` >= 1 buffers of bytes.
  AccessorWriter(tinygltf::Model& model, std::size_t buffers) : m_(model), data_(buffers) {}

  // The buffer the next views go to (< the buffer count given at construction).
  int buffer() const { return buffer_; }
  void set_buffer(int b) { buffer_ = b; }
  // The bytes written to buffer `b` so far (the model builder moves them out when done).
  std::vector<unsigned char>& data(std::size_t b) { return data_[b]; }
  std::size_t buffer_count() const { return data_.size(); }

  // Appends `size` bytes at a 4-byte aligned offset of the current buffer (zero padding before);
  // returns the view index. `target`: a TINYGLTF_TARGET_* value, 0 for none.
  int add_view(const void* bytes, std::size_t size, int target);
  // Sets the byteStride of view `view`.
  void set_stride(int view, std::size_t stride);
  // Names the meshopt filter (meshopt_encode.h) whose output view `view` holds.
  void set_filter(int view, std::string filter) { filters_[view] = std::move(filter); }
  const std::map<int, std::string>& filters() const { return filters_; }

  // A FLOAT accessor over `count` elements of `components` floats (1..4) in `view`; with `view` < 0
  // it has no buffer view (Draco). `min_max`: min/max per component of `values`.
  int float_accessor(const std::vector<float>& values, int components, std::size_t count, int view,
                     bool min_max);
  // A view holding `values` and a FLOAT accessor over it.
  int float_attribute(const std::vector<float>& values, int components, bool min_max, int target);
  // An integer vertex attribute: a view of `count` elements of `stride` bytes (its byteStride)
  // and an accessor of `components` values of `component_type`.
  int integer_attribute(const void* bytes, std::size_t count, std::size_t stride, int component_type,
                        int components, bool normalized);
  // An index accessor and its view: UNSIGNED_SHORT when short_indices(vertex_count), else UNSIGNED_INT.
  int index_accessor(const std::vector<std::uint32_t>& indices, std::size_t vertex_count);
  // An accessor without a view; returns its index.
  int add_accessor_without_view(int type, std::size_t count, int component_type);
  // Sets accessor `accessor`'s min and max (one value per component).
  void set_bounds(int accessor, std::vector<double> min, std::vector<double> max);
  // The view accessor `accessor` reads.
  int view_of(int accessor) const;

  // Whether indices into `vertex_count` vertices fit UNSIGNED_SHORT.
  static bool short_indices(std::size_t vertex_count) { return vertex_count <= 0xFFFF; }
  // TINYGLTF_TYPE_SCALAR, VEC2, VEC3 or VEC4 for 1, 2, 3 or 4 components.
  static int type_for(int components);

 private:
  tinygltf::Model& m_;
  std::vector<std::vector<unsigned char>> data_;  // per buffer
  int buffer_ = 0;
  std::map<int, std::string> filters_;
};

}  // namespace sylva::gltf::detail
