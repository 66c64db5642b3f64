// Every candidate is prepared once: its grid for its own switch distance, its primitive count.
// The measured choice then asks for the same level's file again and again (other grids, other
// distances), so the re-deflated PNGs and the nearer-line scenes are kept here.
#include "stages/pack/candidates.h"

#include <algorithm>
#include <cstdio>
#include <stdexcept>

#include "libs/gltf/optimize.h"
#include "libs/image/png.h"
#include "libs/lodmodel/lod_model.h"
#include "stages/pack/position_grid.h"

namespace sylva::pack {

Prepared::Prepared(const SpeciesInput& in, const PackOptions& options) : in_(in), options_(options) {
  parsed = parse_chain(in);
  if (!(options.min_saving >= 0 && options.min_saving < 1))
    throw std::invalid_argument("min_saving must lie in [0, 1)");
  w.format = gltf::FileFormat::kGlb;
  w.meshopt = options.compression == Compression::kMeshopt;
  w.meshopt_merge_views = w.meshopt;
  w.draco.enabled = options.compression == Compression::kDraco;
  w.quantize.enabled = options.quantize && !w.draco.enabled;
  w.quantize.normal_bits = options.normal_bits;
  w.quantize.texcoord_bits = options.texcoord_bits;
  for (std::size_t i = 0; i < in.levels.size(); ++i) {
    Candidate c;
    c.source_level = i;
    c.scene = &in.levels[i];
    c.epsilon_m = parsed.levels[i].epsilon_m;
    c.pixel_error_px = parsed.levels[i].pixel_error_px;
    c.switch_distance_m = parsed.levels[i].switch_distance_m;
    candidates.push_back(std::move(c));
  }
  if (in.impostor) {
    Candidate c;
    c.impostor = true;
    c.scene = &in.impostor->scene;
    c.epsilon_m = in.impostor->epsilon_m;
    c.pixel_error_px = in.impostor->pixel_error_px;
    c.switch_distance_m = std::max(in.impostor->switch_distance_m, parsed.levels[0].switch_distance_m);
    candidates.push_back(std::move(c));
  }
  for (Candidate& c : candidates) {
    c.primitives = primitives_of(*c.scene);
    for (const gltf::Mesh& mesh : c.scene->meshes) c.extent.push_back(mesh_extent(mesh));
    set_grid(c, c.switch_distance_m);
  }
}

void Prepared::set_grid(Candidate& c, double d) const {
  const std::size_t meshes = c.scene->meshes.size();
  c.fine.assign(meshes, 0);
  if (!w.quantize.enabled) {
    c.bits.assign(meshes, 0);
    c.grid = {};
    c.grid.position_float = true;
    return;
  }
  const double scale = c.switch_distance_m > 0 && d < c.switch_distance_m ? d / c.switch_distance_m : 1.0;
  const double epsilon = c.epsilon_m * scale;
  c.float_error = options_.position_error * epsilon;
  std::vector<int> bits;
  for (std::size_t m = 0; m < meshes; ++m) {
    const PositionGrid g =
        position_grid(c.scene->meshes[m], epsilon, options_.position_error, options_.position_error_max);
    bits.push_back(g.bits);
    c.fine[m] = g.bits == 0 || g.bits > options_.position_bits_min;
  }
  set_bits(c, std::move(bits));
}

void Prepared::draw_from(Candidate& c, double d) {
  set_grid(c, d);
  if (!options_.nearer_line_coverage || c.impostor || !(d < c.switch_distance_m)) return;
  const gltf::Scene& level = in_.levels[c.source_level];
  auto blended_lines = [&](const gltf::Primitive& p) {
    return p.mode == gltf::PrimitiveMode::kLines && p.material >= 0 && !p.colors.empty() &&
           level.materials[std::size_t(p.material)].alpha_mode == gltf::AlphaMode::kBlend;
  };
  bool any = false;
  for (const gltf::Mesh& m : level.meshes)
    any = any || std::any_of(m.primitives.begin(), m.primitives.end(), blended_lines);
  if (!any) return;
  auto [it, added] = drawn_from_.try_emplace({c.source_level, d});
  if (added) {
    it->second = level;
    const double scale = c.switch_distance_m / d;
    for (gltf::Mesh& m : it->second.meshes)
      for (gltf::Primitive& p : m.primitives)
        if (blended_lines(p))
          for (std::size_t i = 3; i < p.colors.size(); i += 4)
            p.colors[i] = float(lodmodel::line_alpha_at(p.colors[i], scale));
  }
  c.scene = &it->second;
}

void Prepared::set_bits(Candidate& c, std::vector<int> bits) const {
  c.bits = std::move(bits);
  c.grid = {};
  for (std::size_t m = 0; m < c.bits.size(); ++m) {
    c.grid.position_bits = std::max(c.grid.position_bits, c.bits[m]);
    if (c.bits[m] > 0) {
      c.grid.position_error_m = std::max(c.grid.position_error_m, grid_error(c.extent[m], c.bits[m]));
    } else {
      c.grid.position_float = true;
      // Float positions: exact, or within position_error x epsilon through the EXPONENTIAL filter.
      if (w.meshopt) c.grid.position_error_m = std::max(c.grid.position_error_m, c.float_error);
    }
  }
}

std::string Prepared::encode(gltf::Scene s, std::vector<int> bits, std::vector<double> float_error) {
  for (gltf::Image& im : s.images) im.bytes = smaller_png(im.bytes);
  w.quantize.position_bits = std::move(bits);
  w.quantize.float_position_error = std::move(float_error);
  if (options_.optimize) gltf::optimize_scene(s, gltf::OptimizeOrder::kSize);
  nlohmann::json extras = s.extras.is_object() ? s.extras : nlohmann::json::object();
  extras["sylva_stage"] = "pack";
  extras["species"] = in_.species;
  s.extras = std::move(extras);
  return gltf::encode(s, w);
}

std::string Prepared::level_file(const Candidate& c) {
  gltf::Scene s = *c.scene;
  if (!c.impostor) {
    for (gltf::Mesh& m : s.meshes) m.extras = nullptr;
    for (gltf::Node& n : s.nodes) n.extras = nullptr;
  }
  return encode(std::move(s), c.bits, std::vector<double>(c.scene->meshes.size(), c.float_error));
}

// The stages write their PNGs at zlib level 6 (libs/image encode_png); a shipped file is
// written once and read by every client, so the pack spends level 9 on it. Another colour type
// or bit depth is left as it is because decode_png would convert it. The measured choice encodes
// a level's file several times, hence the map.
const std::string& Prepared::smaller_png(const std::string& bytes) {
  const auto it = smaller_png_.find(bytes);
  if (it != smaller_png_.end()) return it->second;
  std::string out = bytes;
  // PNG signature (8), IHDR length and type (8), width, height (8), bit depth, colour type.
  const bool rgba8 = bytes.size() > 26 && bytes.compare(0, 8, "\x89PNG\r\n\x1a\n") == 0 &&
                     bytes.compare(12, 4, "IHDR") == 0 && bytes[24] == 8 && bytes[25] == 6;
  if (rgba8) {
    const image::Image pixels = image::decode_png(bytes);
    const std::vector<std::uint8_t> png = image::encode_png(pixels, image::PngOptions{9});
    const std::string_view v(reinterpret_cast<const char*>(png.data()), png.size());
    if (png.size() < bytes.size() && image::decode_png(v) == pixels) out.assign(v);
  }
  return smaller_png_.emplace(bytes, std::move(out)).first->second;
}

std::string describe(double d) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", d);
  return buf;
}

std::string level_name(const Candidate& c) {
  return c.impostor ? std::string("the impostor") : "level " + std::to_string(c.source_level);
}

}  // namespace sylva::pack
