// Developer preview of a preset: front (X–Y) and side (Z–Y) orthographic drawings of the
// skeleton and foliage, plus the tree's statistics on stdout.
//   generate_preview configs/species/oak.yaml adult 1 out/oak.png [levels]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>

#include "libs/image/png.h"
#include "libs/tree/stats.h"
#include "stages/generate/preset.h"
#include "stages/generate/textures.h"
#include "stages/generate/weber_penn.h"

using namespace sylva;

int main(int argc, char** argv) {
  if (argc < 5) {
    std::fprintf(stderr, "usage: generate_preview PRESET AGE SEED OUT.png [LEVELS]\n");
    return 2;
  }
  try {
    const auto species = generate::load_species_preset(argv[1]);
    const auto& v = species.age(argv[2]);
    generate::GenerateOptions o;
    o.levels = argc > 5 ? std::stoi(argv[5]) : 0;
    o.max_node_spacing = 0.5;
    o.name = species.species + "/" + v.age;
    Rng rng(std::stoull(argv[3]), "tree");
    const auto t0 = std::chrono::steady_clock::now();
    const tree::Tree t = generate::generate_tree(v.params, o, rng);
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    const tree::TreeStats s = tree::compute_stats(t);
    std::printf("%sgenerated in %.1f ms; expected height %.1f..%.1f m\n", tree::format_stats(s).c_str(), ms,
                v.height_min, v.height_max);
    const int h = 800, w = 1600;
    image::Image img(w, h, {235, 235, 230, 255});
    const double extent = std::max({s.bounds_max.y - s.bounds_min.y, s.bounds_max.x - s.bounds_min.x,
                                    s.bounds_max.z - s.bounds_min.z, 0.1}) *
                          1.05;
    const double px_per_m = h / extent;
    auto stamp = [&](int view, tree::Vec3 p, double r, image::Rgba8 c) {
      const double hx = view == 0 ? p.x : p.z;
      const double cx = w / 4.0 + view * w / 2.0 + hx * px_per_m;
      const double cy = h - 4 - (p.y - s.bounds_min.y) * px_per_m;
      const double rp = std::max(0.5, r * px_per_m);
      for (int y = static_cast<int>(cy - rp); y <= static_cast<int>(cy + rp); ++y)
        for (int x = static_cast<int>(cx - rp); x <= static_cast<int>(cx + rp); ++x)
          if (x >= 0 && y >= 0 && x < w && y < h &&
              (x - cx) * (x - cx) + (y - cy) * (y - cy) <= rp * rp + 0.25)
            img.set(x, y, c);
    };
    for (int view = 0; view < 2; ++view) {
      for (const auto& b : t.branches) {
        const image::Rgba8 c = b.level == 0 ? image::Rgba8{70, 45, 30, 255} : image::Rgba8{110, 80, 55, 255};
        for (std::size_t k = 0; k + 1 < b.nodes.size(); ++k) {
          const auto a = b.nodes[k], e = b.nodes[k + 1];
          const double len = tree::length(e.position - a.position) * px_per_m;
          const int steps = std::max(1, static_cast<int>(len * 2));
          for (int i = 0; i <= steps; ++i) {
            const double f = static_cast<double>(i) / steps;
            stamp(view, a.position + (e.position - a.position) * f, a.radius + (e.radius - a.radius) * f, c);
          }
        }
      }
      for (const auto& l : t.leaves)
        stamp(view, tree::to_double(l.position) + tree::to_double(l.direction) * (l.length * 0.5),
              l.width * 0.4, {60, 120, 40, 255});
      for (const auto& n : t.needles) stamp(view, tree::to_double(n.tip), n.radius * 2, {30, 80, 40, 255});
    }
    image::write_png(img, argv[4]);
    // The species' textures beside it: <out>.bark.png, <out>.leaves.png.
    Rng bark_rng(std::stoull(argv[3]), "bark"), leaf_rng(std::stoull(argv[3]), "leaves");
    for (int which = 0; which < 2; ++which) {
      const generate::Rgba8 px = which == 0 ? generate::make_bark_texture(species.bark, 256, bark_rng)
                                            : generate::make_leaf_atlas(species.leaf, 256, leaf_rng);
      image::Image tex(px.width, px.height);
      tex.bytes() = px.pixels;
      image::write_png(tex, std::string(argv[4]) + (which == 0 ? ".bark.png" : ".leaves.png"));
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
