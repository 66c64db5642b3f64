// Views are appended in the order the model builder asks for them, so the layout (and the file's
// bytes) follow the scene's order alone.
#include "libs/gltf/accessor_writer.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <limits>
#include <utility>

namespace sylva::gltf::detail {

int AccessorWriter::add_view(const void* bytes, std::size_t size, int target) {
  std::vector<unsigned char>& data = data_[std::size_t(buffer_)];
  while (data.size() % 4 != 0) data.push_back(0);
  tinygltf::BufferView v;
  v.buffer = buffer_;
  v.byteOffset = data.size();
  v.byteLength = size;
  v.target = target;
  const auto* b = static_cast<const unsigned char*>(bytes);
  data.insert(data.end(), b, b + size);
  m_.bufferViews.push_back(v);
  return static_cast<int>(m_.bufferViews.size() - 1);
}

void AccessorWriter::set_stride(int view, std::size_t stride) {
  m_.bufferViews[std::size_t(view)].byteStride = stride;
}

int AccessorWriter::type_for(int components) {
  switch (components) {
    case 1:
      return TINYGLTF_TYPE_SCALAR;
    case 2:
      return TINYGLTF_TYPE_VEC2;
    case 3:
      return TINYGLTF_TYPE_VEC3;
    default:
      return TINYGLTF_TYPE_VEC4;
  }
}

int AccessorWriter::float_accessor(const std::vector<float>& values, int components, std::size_t count,
                                   int view, bool min_max) {
  tinygltf::Accessor a;
  a.bufferView = view;
  a.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
  a.type = type_for(components);
  a.count = count;
  if (min_max) {
    a.minValues.assign(static_cast<std::size_t>(components), std::numeric_limits<double>::infinity());
    a.maxValues.assign(static_cast<std::size_t>(components), -std::numeric_limits<double>::infinity());
    for (std::size_t i = 0; i < values.size(); ++i) {
      const std::size_t c = i % static_cast<std::size_t>(components);
      a.minValues[c] = std::min<double>(a.minValues[c], values[i]);
      a.maxValues[c] = std::max<double>(a.maxValues[c], values[i]);
    }
  }
  m_.accessors.push_back(a);
  return static_cast<int>(m_.accessors.size() - 1);
}

int AccessorWriter::float_attribute(const std::vector<float>& values, int components, bool min_max,
                                    int target) {
  const int view = add_view(values.data(), values.size() * sizeof(float), target);
  return float_accessor(values, components, values.size() / static_cast<std::size_t>(components), view,
                        min_max);
}

int AccessorWriter::integer_attribute(const void* bytes, std::size_t count, std::size_t stride,
                                      int component_type, int components, bool normalized) {
  const int view = add_view(bytes, count * stride, TINYGLTF_TARGET_ARRAY_BUFFER);
  set_stride(view, stride);
  tinygltf::Accessor a;
  a.bufferView = view;
  a.componentType = component_type;
  a.type = type_for(components);
  a.count = count;
  a.normalized = normalized;
  m_.accessors.push_back(a);
  return static_cast<int>(m_.accessors.size() - 1);
}

int AccessorWriter::index_accessor(const std::vector<std::uint32_t>& indices, std::size_t vertex_count) {
  tinygltf::Accessor a;
  a.type = TINYGLTF_TYPE_SCALAR;
  a.count = indices.size();
  if (short_indices(vertex_count)) {
    std::vector<std::uint16_t> narrow(indices.begin(), indices.end());
    a.bufferView = add_view(narrow.data(), narrow.size() * 2, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
    a.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
  } else {
    a.bufferView = add_view(indices.data(), indices.size() * 4, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
    a.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
  }
  m_.accessors.push_back(a);
  return static_cast<int>(m_.accessors.size() - 1);
}

int AccessorWriter::add_accessor_without_view(int type, std::size_t count, int component_type) {
  tinygltf::Accessor a;
  a.type = type;
  a.count = count;
  a.componentType = component_type;
  m_.accessors.push_back(a);
  return static_cast<int>(m_.accessors.size() - 1);
}

void AccessorWriter::set_bounds(int accessor, std::vector<double> min, std::vector<double> max) {
  tinygltf::Accessor& a = m_.accessors[std::size_t(accessor)];
  a.minValues = std::move(min);
  a.maxValues = std::move(max);
}

int AccessorWriter::view_of(int accessor) const { return m_.accessors[std::size_t(accessor)].bufferView; }

}  // namespace sylva::gltf::detail
