// Values are quantised with meshoptimizer's own quantisers (meshopt_quantizeUnorm/Snorm and its
// filters), so what gltfpack and the meshopt decoder expect is what is written; the integer
// layouts keep every element 4-byte aligned, as KHR_mesh_quantization requires.
#include "libs/gltf/quantized_attributes.h"

#include <meshoptimizer.h>
#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <utility>

namespace sylva::gltf::detail {
namespace {

// v in [0, 1] on the grid of `bits`-bit steps inside a `to`-bit normalized integer: k * 2^(to -
// bits) with k = meshopt_quantizeUnorm(v * (2^to - 1) / (2^to - 2^(to - bits)), bits), so the low
// bits are zero (the codecs compress them away) and the integer decodes to within half a
// `bits`-bit step of v (within one step for v in the top step, which clamps to the largest k).
unsigned on_grid(float v, int bits, int to) {
  if (bits >= to) return unsigned(meshopt_quantizeUnorm(v, to));
  const double full = double((1u << to) - 1), top = double((1u << to) - (1u << (to - bits)));
  return unsigned(meshopt_quantizeUnorm(float(double(v) * full / top), bits)) << (to - bits);
}

PositionGrid grid_of(const Mesh& mesh, int bits) {
  PositionGrid g;
  g.bits = bits;
  std::array<double, 3> hi{};
  g.lo.fill(std::numeric_limits<double>::infinity());
  hi.fill(-std::numeric_limits<double>::infinity());
  for (const Primitive& p : mesh.primitives)
    for (std::size_t i = 0; i < p.positions.size(); ++i) {
      g.lo[i % 3] = std::min<double>(g.lo[i % 3], p.positions[i]);
      hi[i % 3] = std::max<double>(hi[i % 3], p.positions[i]);
    }
  for (int c = 0; c < 3; ++c) g.extent = std::max(g.extent, hi[std::size_t(c)] - g.lo[std::size_t(c)]);
  g.step = g.extent > 0 ? g.extent / double((1u << bits) - 1) : 1.0;
  return g;
}

}  // namespace

bool in_unit_range(const std::vector<float>& v) {
  return std::all_of(v.begin(), v.end(), [](float x) { return x >= 0.f && x <= 1.f; });
}

QuantizePlan plan_quantization(const Scene& s, const QuantizeOptions& q) {
  QuantizePlan plan;
  plan.grids.assign(s.meshes.size(), PositionGrid{});
  for (const auto& [name, bits] : {std::pair<const char*, int>{"normal_bits", q.normal_bits},
                                   {"texcoord_bits", q.texcoord_bits},
                                   {"color_bits", q.color_bits}})
    if (bits < 1 || bits > 16)
      throw GltfError(std::string("quantize.") + name + " is " + std::to_string(bits) + ", expected 1..16");
  plan.uv_grid.assign(s.materials.size(), 0);
  for (std::size_t i = 0; i < s.materials.size(); ++i)
    plan.uv_grid[i] =
        s.materials[i].base_color_texture.image >= 0 || s.materials[i].normal_texture.image >= 0;
  for (const Mesh& mesh : s.meshes)
    for (const Primitive& p : mesh.primitives)
      if (p.material >= 0 && !p.texcoords.empty() && !in_unit_range(p.texcoords))
        plan.uv_grid[std::size_t(p.material)] = 0;
  std::vector<char> instanced(s.meshes.size(), 0);
  for (const Node& n : s.nodes)
    if (n.mesh >= 0 && !n.instances.empty()) instanced[std::size_t(n.mesh)] = 1;
  for (std::size_t m = 0; m < s.meshes.size() && m < q.position_bits.size(); ++m) {
    const int bits = q.position_bits[m];
    if (bits < 0 || bits > 16)
      throw GltfError("quantize.position_bits[" + std::to_string(m) + "] is " + std::to_string(bits) +
                      ", expected 0..16");
    if (bits == 0 || instanced[m]) continue;
    plan.grids[m] = grid_of(s.meshes[m], bits);
  }
  return plan;
}

int AttributeQuantizer::integer_attribute(const void* bytes, std::size_t count, std::size_t stride,
                                          int component_type, int components, bool normalized) {
  wrote_integers_ = true;
  return views_.integer_attribute(bytes, count, stride, component_type, components, normalized);
}

int AttributeQuantizer::grid_positions(const std::vector<float>& v, const PositionGrid& g) {
  const std::size_t n = v.size() / 3;
  std::vector<std::uint16_t> q(n * 4, 0);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t c = 0; c < 3; ++c) {
      const double t = g.extent > 0 ? (double(v[i * 3 + c]) - g.lo[c]) / g.extent : 0.0;
      q[i * 4 + c] = static_cast<std::uint16_t>(meshopt_quantizeUnorm(float(t), g.bits));
    }
  const int acc = integer_attribute(q.data(), n, 8, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, 3, false);
  std::vector<double> lo(3, std::numeric_limits<double>::infinity());
  std::vector<double> hi(3, -std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t c = 0; c < 3; ++c) {
      lo[c] = std::min<double>(lo[c], q[i * 4 + c]);
      hi[c] = std::max<double>(hi[c], q[i * 4 + c]);
    }
  views_.set_bounds(acc, std::move(lo), std::move(hi));
  return acc;
}

int AttributeQuantizer::exponential_positions(const std::vector<float>& v, double max_error) {
  const std::size_t n = v.size() / 3;
  std::vector<unsigned char> encoded(n * 12);
  auto decodes_within = [&](int bits) {
    meshopt_encodeFilterExp(encoded.data(), n, 12, bits, v.data());
    std::vector<unsigned char> decoded = encoded;
    meshopt_decodeFilterExp(decoded.data(), n, 12);
    const float* d = reinterpret_cast<const float*>(decoded.data());
    for (std::size_t i = 0; i < n; ++i) {
      double e2 = 0;
      for (std::size_t c = 0; c < 3; ++c)
        e2 += (double(d[i * 3 + c]) - v[i * 3 + c]) * (double(d[i * 3 + c]) - v[i * 3 + c]);
      if (std::sqrt(e2) > max_error) return false;
    }
    return true;
  };
  int lo = 1, hi = 24;  // 24 bits keep a float's whole mantissa
  while (lo < hi) {
    const int mid = (lo + hi) / 2;
    if (decodes_within(mid)) {
      hi = mid;
    } else {
      lo = mid + 1;
    }
  }
  meshopt_encodeFilterExp(encoded.data(), n, 12, lo, v.data());
  std::vector<float> decoded(n * 3);
  std::memcpy(decoded.data(), encoded.data(), encoded.size());
  meshopt_decodeFilterExp(decoded.data(), n, 12);
  const int view = views_.add_view(encoded.data(), encoded.size(), TINYGLTF_TARGET_ARRAY_BUFFER);
  views_.set_stride(view, 12);
  views_.set_filter(view, "EXPONENTIAL");
  return views_.float_accessor(decoded, 3, n, view, true);
}

int AttributeQuantizer::normals(const std::vector<float>& v) {
  const int bits = q_.normal_bits;
  const bool wide = bits > 8;
  const std::size_t n = v.size() / 3, stride = wide ? 8 : 4;
  std::vector<unsigned char> out(n * stride, 0);
  if (meshopt_) {
    std::vector<float> v4(n * 4, 0.f);
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t c = 0; c < 3; ++c) v4[i * 4 + c] = v[i * 3 + c];
    meshopt_encodeFilterOct(out.data(), n, stride, bits, v4.data());
  } else {
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t c = 0; c < 3; ++c) {
        if (wide) {
          const auto k = static_cast<std::int16_t>(meshopt_quantizeSnorm(v[i * 3 + c], 16));
          std::memcpy(out.data() + i * 8 + c * 2, &k, 2);
        } else {
          out[i * 4 + c] =
              static_cast<unsigned char>(static_cast<std::int8_t>(meshopt_quantizeSnorm(v[i * 3 + c], 8)));
        }
      }
  }
  const int acc = integer_attribute(
      out.data(), n, stride, wide ? TINYGLTF_COMPONENT_TYPE_SHORT : TINYGLTF_COMPONENT_TYPE_BYTE, 3, true);
  if (meshopt_) views_.set_filter(views_.view_of(acc), "OCTAHEDRAL");
  return acc;
}

int AttributeQuantizer::grid_texcoords(const std::vector<float>& v) {
  const int bits = q_.texcoord_bits;
  std::vector<std::uint16_t> q(v.size());
  for (std::size_t i = 0; i < v.size(); ++i)
    q[i] = static_cast<std::uint16_t>(meshopt_quantizeUnorm(v[i], bits));
  return integer_attribute(q.data(), v.size() / 2, 4, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, 2, true);
}

int AttributeQuantizer::unorm(const std::vector<float>& v, int components, int bits, bool allow_byte) {
  const std::size_t n = v.size() / std::size_t(components);
  const bool byte = allow_byte && bits <= 8;
  const std::size_t stride = (std::size_t(components) * (byte ? 1 : 2) + 3) / 4 * 4;
  std::vector<unsigned char> out(n * stride, 0);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t c = 0; c < std::size_t(components); ++c) {
      const unsigned k = on_grid(v[i * std::size_t(components) + c], bits, byte ? 8 : 16);
      if (byte) {
        out[i * stride + c] = static_cast<unsigned char>(k);
      } else {
        const auto k16 = static_cast<std::uint16_t>(k);
        std::memcpy(out.data() + i * stride + c * 2, &k16, 2);
      }
    }
  return integer_attribute(
      out.data(), n, stride,
      byte ? TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE : TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, components,
      true);
}

}  // namespace sylva::gltf::detail
