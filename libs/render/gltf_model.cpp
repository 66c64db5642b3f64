// Checked reads of a parsed glTF's accessors and buffer views (gltf_model.h): every range is
// checked before it is read or allocated, so a corrupt count or offset fails with one line
// instead of reading out of bounds or allocating gigabytes.
#include "libs/render/gltf_model.h"

#include <algorithm>
#include <cctype>
#include <cstring>

#include "libs/render/gltf_scene.h"

namespace sylva::render::detail {
namespace {

float component(const unsigned char* p, int type, bool normalized) {
  switch (type) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT: {
      float v;
      std::memcpy(&v, p, 4);
      return v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: {
      const float v = float(*p);
      return normalized ? v / 255.f : v;
    }
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
      const float v = float(std::int8_t(*p));
      return normalized ? std::max(v / 127.f, -1.f) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      std::uint16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? float(v) / 65535.f : float(v);
    }
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      std::int16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? std::max(float(v) / 32767.f, -1.f) : float(v);
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
      std::uint32_t v;
      std::memcpy(&v, p, 4);
      return float(v);
    }
    default:
      return 0.f;
  }
}

}  // namespace

void GltfModel::fail(const std::string& why) const { throw SceneLoadError(file_ + ": error: " + why); }

const tinygltf::BufferView& GltfModel::buffer_view(int view, const std::string& what) const {
  if (view < 0 || std::size_t(view) >= m_.bufferViews.size())
    fail(what + ": buffer view " + std::to_string(view) + " does not exist");
  return m_.bufferViews[std::size_t(view)];
}

const unsigned char* GltfModel::view_data(int view, std::size_t offset, std::size_t count, std::size_t stride,
                                          std::size_t elem_size, const std::string& what) const {
  const tinygltf::BufferView& bv = buffer_view(view, what);
  if (bv.buffer < 0 || std::size_t(bv.buffer) >= m_.buffers.size())
    fail(what + ": buffer " + std::to_string(bv.buffer) + " does not exist");
  const tinygltf::Buffer& buf = m_.buffers[std::size_t(bv.buffer)];
  if (bv.byteOffset > buf.data.size() || bv.byteLength > buf.data.size() - bv.byteOffset)
    fail(what + ": buffer view runs past the end of its buffer");
  // Overflow-safe form of offset + stride * (count - 1) + elem_size <= byteLength.
  if (count > 0 && (stride == 0 || offset > bv.byteLength || elem_size > bv.byteLength - offset ||
                    (count - 1) > (bv.byteLength - offset - elem_size) / stride))
    fail(what + ": data runs past the end of its buffer view");
  return buf.data.data() + bv.byteOffset + offset;
}

const tinygltf::Accessor& GltfModel::accessor(int index, const std::string& what) const {
  if (index < 0 || std::size_t(index) >= m_.accessors.size())
    fail(what + ": accessor " + std::to_string(index) + " does not exist");
  const tinygltf::Accessor& acc = m_.accessors[std::size_t(index)];
  // Without a buffer view an accessor is zeros (plus sparse values) of any declared count: the
  // count is all that bounds the allocation.
  if (acc.count > max_count_)
    fail(what + ": accessor " + std::to_string(index) + " declares " + std::to_string(acc.count) +
         " elements, more than the limit of " + std::to_string(max_count_));
  return acc;
}

AttributeData GltfModel::read_accessor(int index, const std::string& what) const {
  const tinygltf::Accessor& acc = accessor(index, what);
  const int ncomp = tinygltf::GetNumComponentsInType(std::uint32_t(acc.type));
  const int csize = tinygltf::GetComponentSizeInBytes(std::uint32_t(acc.componentType));
  if (ncomp <= 0 || csize <= 0 || ncomp > 16)
    fail(what + ": accessor " + std::to_string(index) + " has an invalid type");
  const std::size_t elem = std::size_t(ncomp) * std::size_t(csize);
  // Check the data range before allocating: a corrupt count must not allocate gigabytes.
  const unsigned char* base = nullptr;
  std::size_t stride = elem;
  if (acc.bufferView >= 0) {
    if (buffer_view(acc.bufferView, what).byteStride) stride = buffer_view(acc.bufferView, what).byteStride;
    base = view_data(acc.bufferView, acc.byteOffset, acc.count, stride, elem, what);
  }
  AttributeData out;
  out.components = ncomp;
  out.count = acc.count;
  out.values.assign(acc.count * std::size_t(ncomp), 0.f);
  if (base) {
    for (std::size_t i = 0; i < acc.count; ++i)
      for (int c = 0; c < ncomp; ++c)
        out.values[i * std::size_t(ncomp) + std::size_t(c)] =
            component(base + i * stride + std::size_t(c * csize), acc.componentType, acc.normalized);
  }
  if (acc.sparse.isSparse) {
    const std::size_t n = std::size_t(std::max(acc.sparse.count, 0));
    const int itype = acc.sparse.indices.componentType;
    const int isize = tinygltf::GetComponentSizeInBytes(std::uint32_t(itype));
    if (isize <= 0) fail(what + ": sparse accessor has invalid index type");
    const unsigned char* idx =
        view_data(acc.sparse.indices.bufferView, std::size_t(acc.sparse.indices.byteOffset), n,
                  std::size_t(isize), std::size_t(isize), what);
    const unsigned char* val = view_data(acc.sparse.values.bufferView,
                                         std::size_t(acc.sparse.values.byteOffset), n, elem, elem, what);
    for (std::size_t k = 0; k < n; ++k) {
      const auto target = std::size_t(component(idx + k * std::size_t(isize), itype, false));
      if (target >= acc.count) fail(what + ": sparse index out of range");
      for (int c = 0; c < ncomp; ++c)
        out.values[target * std::size_t(ncomp) + std::size_t(c)] =
            component(val + k * elem + std::size_t(c * csize), acc.componentType, acc.normalized);
    }
  }
  return out;
}

std::vector<std::uint32_t> GltfModel::read_indices(int index, const std::string& what) const {
  const tinygltf::Accessor& acc = accessor(index, what);
  if (acc.type != TINYGLTF_TYPE_SCALAR || (acc.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
                                           acc.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
                                           acc.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT))
    fail(what + ": indices must be unsigned byte, short or int scalars");
  // UNSIGNED_INT values above 2^24 do not survive a float; read integers directly.
  const int csize = tinygltf::GetComponentSizeInBytes(std::uint32_t(acc.componentType));
  if (acc.bufferView < 0 || acc.sparse.isSparse) {
    const AttributeData a = read_accessor(index, what);
    std::vector<std::uint32_t> out(a.count, 0);
    for (std::size_t i = 0; i < out.size(); ++i) out[i] = std::uint32_t(a.values[i]);
    return out;
  }
  const std::size_t stride = buffer_view(acc.bufferView, what).byteStride
                                 ? buffer_view(acc.bufferView, what).byteStride
                                 : std::size_t(csize);
  const unsigned char* base =
      view_data(acc.bufferView, acc.byteOffset, acc.count, stride, std::size_t(csize), what);
  // Allocated once view_data has checked that the view holds `count` indices.
  std::vector<std::uint32_t> out(acc.count, 0);
  for (std::size_t i = 0; i < acc.count; ++i) {
    const unsigned char* p = base + i * stride;
    if (csize == 1) {
      out[i] = *p;
    } else if (csize == 2) {
      std::uint16_t v;
      std::memcpy(&v, p, 2);
      out[i] = v;
    } else {
      std::memcpy(&out[i], p, 4);
    }
  }
  return out;
}

std::string decode_uri(const std::string& uri) {
  std::string out;
  for (std::size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] == '%' && i + 2 < uri.size() && std::isxdigit(static_cast<unsigned char>(uri[i + 1])) &&
        std::isxdigit(static_cast<unsigned char>(uri[i + 2]))) {
      out += char(std::stoi(uri.substr(i + 1, 2), nullptr, 16));
      i += 2;
    } else {
      out += uri[i];
    }
  }
  return out;
}

}  // namespace sylva::render::detail
