// Forest views (forest_view.h). Each view builds its own Scene: the textures and materials of
// the (species, level) meshes it uses and those meshes with the chosen trees' world matrices as
// instances, so the renderer draws one instanced call per primitive for the opaque and masked
// parts (its BLEND pass still draws per instance, far to near); (hemi-)octahedral impostor levels
// become Scene::impostors sets (the atlas shared, not copied, between views).
#include "libs/render/forest_view.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <exception>

#include "libs/image/image_io.h"
#include "libs/impostor/impostor_json.h"
#include "libs/render/gltf_scene.h"
#include "libs/render/impostor_atlas.h"
#include "libs/render/line_merge.h"

namespace sylva::render {

namespace {

Mat4 to_mat4(const std::array<double, 16>& m) {
  Mat4 out;
  for (int i = 0; i < 16; ++i) out.data()[i] = float(m[std::size_t(i)]);
  return out;
}

Bounds to_bounds(const forest::Box3& b) {
  Bounds o;
  o.extend(Vec3(float(b.min[0]), float(b.min[1]), float(b.min[2])));
  o.extend(Vec3(float(b.max[0]), float(b.max[1]), float(b.max[2])));
  return o;
}

double box_distance(const Bounds& b, const Vec3& p) {
  double s = 0;
  for (int k = 0; k < 3; ++k) {
    const double e = p[k] < b.min[k] ? b.min[k] - p[k] : (p[k] > b.max[k] ? p[k] - b.max[k] : 0.0);
    s += e * e;
  }
  return std::sqrt(s);
}

// The six planes (a, b, c, d), inside where a x + b y + c z + d >= 0 (Gribb & Hartmann).
std::array<Vec4, 6> frustum_planes(const Mat4& view_proj) {
  std::array<Vec4, 6> p;
  const Eigen::RowVector4f r0 = view_proj.row(0), r1 = view_proj.row(1), r2 = view_proj.row(2),
                           r3 = view_proj.row(3);
  const Eigen::RowVector4f rows[6] = {r3 + r0, r3 - r0, r3 + r1, r3 - r1, r3 + r2, r3 - r2};
  for (int i = 0; i < 6; ++i) p[std::size_t(i)] = rows[i].transpose();
  return p;
}

bool outside(const std::array<Vec4, 6>& planes, const Bounds& b) {
  for (const Vec4& pl : planes) {
    // The box corner furthest along the plane's normal.
    const Vec3 v(pl.x() >= 0 ? b.max.x() : b.min.x(), pl.y() >= 0 ? b.max.y() : b.min.y(),
                 pl.z() >= 0 ? b.max.z() : b.min.z());
    if (pl.x() * v.x() + pl.y() * v.y() + pl.z() * v.z() + pl.w() < 0) return true;
  }
  return false;
}

// Appends `src` (its textures, materials and meshes) to `dst` with each mesh drawn at `worlds`;
// each mesh's geometry is named as src's (Mesh::shared_geometry).
void append(Scene& dst, const std::shared_ptr<const Scene>& shared, const std::vector<Mat4>& worlds,
            std::size_t& primitives) {
  const Scene& src = *shared;
  const int tex0 = int(dst.textures.size()), mat0 = int(dst.materials.size());
  dst.textures.insert(dst.textures.end(), src.textures.begin(), src.textures.end());
  for (Material m : src.materials) {
    if (m.base_color_texture >= 0) m.base_color_texture += tex0;
    dst.materials.push_back(std::move(m));
  }
  for (const Mesh& mesh : src.meshes) {
    Mesh m;
    m.name = mesh.name;
    m.primitives = mesh.primitives;
    m.shared_geometry = std::shared_ptr<const void>(shared, &mesh);
    for (Primitive& p : m.primitives)
      if (p.material >= 0) p.material += mat0;
    m.instances.reserve(worlds.size() * mesh.instances.size());
    for (const Mat4& w : worlds)
      for (const Mat4& local : mesh.instances) m.instances.push_back(w * local);
    for (const Primitive& p : m.primitives) primitives += p.element_count() * m.instances.size();
    dst.meshes.push_back(std::move(m));
  }
}

}  // namespace

ForestView ForestView::load(const std::filesystem::path& instances_json) {
  forest::Forest f = forest::read_instances(instances_json);
  const std::filesystem::path dir = instances_json.parent_path();
  // Every file is read by its own task (GLB/glTF decoding, the impostor maps' PNG decoding and
  // premultiplication are independent); results by index, and the first failure in file order
  // is the one reported, whatever the timing.
  std::vector<std::vector<Scene>> levels(f.species.size());
  std::vector<std::shared_ptr<const ImpostorAtlas>> octahedral(f.species.size());
  Scene ground;
  struct Job {
    std::size_t species, level;  // level == levels.size(): the impostor; species == none: the ground
  };
  constexpr std::size_t kNone = std::size_t(-1);
  std::vector<Job> jobs;
  for (std::size_t s = 0; s < f.species.size(); ++s) {
    levels[s].resize(f.species[s].levels.size());
    for (std::size_t l = 0; l < f.species[s].levels.size(); ++l) jobs.push_back({s, l});
    if (!f.species[s].levels.back().octahedral.empty()) jobs.push_back({s, f.species[s].levels.size()});
  }
  if (!f.ground.empty()) jobs.push_back({kNone, 0});
  std::vector<std::exception_ptr> errors(jobs.size());
  tbb::parallel_for(std::size_t(0), jobs.size(), [&](std::size_t j) {
    try {
      const Job& job = jobs[j];
      if (job.species == kNone) {
        ground = load_gltf_scene(dir / f.ground);
        return;
      }
      const forest::Species& s = f.species[job.species];
      if (job.level < s.levels.size()) {
        levels[job.species][job.level] = load_gltf_scene(dir / s.levels[job.level].file);
        return;
      }
      const forest::Level& last = s.levels.back();
      const impostor::ImpostorInfo info = impostor::read_impostor_json((dir / last.octahedral).string());
      const ImpostorGeometry g = impostor_geometry(info);
      octahedral[job.species] = std::make_shared<const ImpostorAtlas>(
          make_impostor_atlas(s.name + " (" + last.octahedral + ")", image::read_image(dir / info.color_map),
                              image::read_image(dir / info.normal_depth_map), g));
    } catch (...) {
      errors[j] = std::current_exception();
    }
  });
  for (const std::exception_ptr& e : errors)
    if (e) std::rethrow_exception(e);
  ForestView view(std::move(f), std::move(levels));
  if (!ground.meshes.empty()) view.set_ground(std::move(ground));
  for (std::size_t s = 0; s < octahedral.size(); ++s)
    if (octahedral[s]) view.set_octahedral(s, std::move(octahedral[s]));
  return view;
}

ForestView::ForestView(forest::Forest forest, std::vector<std::vector<Scene>> levels)
    : forest_(std::move(forest)),
      full_(forest_.species.size(), std::make_shared<const Scene>()),
      octahedral_(forest_.species.size()),
      ground_(std::make_shared<const Scene>()) {
  for (const forest::Instance& in : forest_.instances) {
    const forest::Species& sp = forest_.species.at(in.species);
    const auto m = forest::instance_matrix(sp, in);
    tree_matrix_.push_back(to_mat4(m));
    tree_bounds_.push_back(to_bounds(forest::transform_box(m, sp.bounds)));
  }
  for (const forest::Tile& t : forest_.tiles) tile_bounds_.push_back(to_bounds(t.bounds));
  for (std::vector<Scene>& species : levels) {
    levels_.emplace_back();
    for (Scene& level : species) {
      merge_line_copies(level);
      levels_.back().push_back(std::make_shared<const Scene>(std::move(level)));
    }
  }
}

void ForestView::set_full_detail(std::size_t species, Scene scene) {
  merge_line_copies(scene);
  full_.at(species) = std::make_shared<const Scene>(std::move(scene));
}

void ForestView::set_ground(Scene ground) { ground_ = std::make_shared<const Scene>(std::move(ground)); }

void ForestView::set_octahedral(std::size_t species, std::shared_ptr<const ImpostorAtlas> atlas) {
  octahedral_.at(species) = std::move(atlas);
}

Bounds ForestView::bounds() const {
  Bounds b;
  for (const Bounds& t : tree_bounds_) b.extend(t);
  b.extend(ground_->bounds());
  return b;
}

namespace {

double distance_scale(const forest::Species& s, const ForestViewOptions& o) {
  return o.pixel_error_px > 0 ? s.pixel_error_px / o.pixel_error_px : 1.0;
}

}  // namespace

int ForestView::parallax_steps_for(std::size_t species, double distance, const ForestViewOptions& o) const {
  const forest::Species& s = forest_.species.at(species);
  const double scale = distance_scale(s, o);
  int steps = ImpostorSet{}.parallax_steps;
  for (const forest::ParallaxStep& p : s.levels.back().parallax)
    if (p.from_m * scale <= distance) steps = p.steps;
  return steps;
}

std::size_t ForestView::level_for(std::size_t species, double distance, const ForestViewOptions& o) const {
  const forest::Species& s = forest_.species.at(species);
  const double scale = distance_scale(s, o);
  std::size_t level = 0;
  for (std::size_t l = 1; l < s.levels.size(); ++l)
    if (s.levels[l].switch_distance_m * scale <= distance) level = l;
  return level;
}

Scene ForestView::view_scene(const Camera& camera, float aspect, const ForestViewOptions& o,
                             ForestViewStats& stats) const {
  const Mat4 vp = camera.projection_matrix(aspect) * camera.view_matrix();
  const auto planes = frustum_planes(vp);
  const std::size_t ns = forest_.species.size();
  std::size_t max_levels = 1;
  for (const auto& s : forest_.species) max_levels = std::max(max_levels, s.levels.size());
  stats = {};
  stats.trees = forest_.instances.size();
  stats.per_level.assign(o.full_detail ? 1 : max_levels, 0);
  // drawn[s][l]: (distance, instance) of the trees species s draws at level l.
  std::vector<std::vector<std::vector<std::pair<double, std::uint32_t>>>> drawn(ns);
  stats.species_trees.resize(ns);
  stats.species_primitives.resize(ns);
  for (std::size_t s = 0; s < ns; ++s) {
    drawn[s].resize(o.full_detail ? 1 : forest_.species[s].levels.size());
    stats.species_trees[s].assign(drawn[s].size(), 0);
    stats.species_primitives[s].assign(drawn[s].size(), 0);
  }
  for (std::size_t t = 0; t < forest_.tiles.size(); ++t) {
    if (o.cull && outside(planes, tile_bounds_[t])) continue;
    bool any = false;
    for (std::uint32_t i : forest_.tiles[t].instances) {
      if (o.cull && outside(planes, tree_bounds_[i])) continue;
      any = true;
      const std::size_t s = forest_.instances[i].species;
      const double d = box_distance(tree_bounds_[i], camera.eye);
      const std::size_t l = o.full_detail ? 0 : level_for(s, d, o);
      drawn[s][l].push_back({d, i});
      ++stats.per_level[l];
      ++stats.species_trees[s][l];
      ++stats.trees_drawn;
    }
    stats.tiles_drawn += any ? 1 : 0;
  }
  // Near to far: the finest levels (the nearest trees) first, each level's trees by distance (ties
  // by instance), so what is drawn later fails the depth test where nearer trees already stand
  // and the rasteriser skips shading it. Opaque and masked results do not depend on this order
  // (depth test) except where two fragments have exactly the same depth; the BLEND pass sorts by
  // depth itself.
  Scene scene;
  scene.source = "forest";
  std::size_t max_level = 0;
  for (std::size_t s = 0; s < ns; ++s) max_level = std::max(max_level, drawn[s].size());
  for (std::size_t l = 0; l < max_level; ++l)
    for (std::size_t s = 0; s < ns; ++s) {
      if (l >= drawn[s].size() || drawn[s][l].empty()) continue;
      if (o.full_detail && full_[s]->meshes.empty())
        throw RenderError("forest view: no full-detail model was given for species '" +
                          forest_.species[s].name + "'");
      std::sort(drawn[s][l].begin(), drawn[s][l].end());
      if (!o.full_detail && octahedral_[s] && l + 1 == forest_.species[s].levels.size()) {
        // One set per parallax step count, nearest (most steps) first; the drawer sorts every
        // impostor of the view far to near across sets.
        for (std::size_t b = 0; b < drawn[s][l].size();) {
          const int steps = parallax_steps_for(s, drawn[s][l][b].first, o);
          ImpostorSet set{octahedral_[s], {}, steps};
          std::size_t e = b;
          for (; e < drawn[s][l].size() && parallax_steps_for(s, drawn[s][l][e].first, o) == steps; ++e)
            set.instances.push_back(tree_matrix_[drawn[s][l][e].second]);
          stats.impostor_steps[steps] += e - b;
          b = e;
          scene.impostors.push_back(std::move(set));
        }
        stats.impostors += drawn[s][l].size();
        stats.primitives += 2 * drawn[s][l].size();
        stats.species_primitives[s][l] += 2 * drawn[s][l].size();
        continue;
      }
      std::vector<Mat4> worlds;
      worlds.reserve(drawn[s][l].size());
      for (const auto& [d, i] : drawn[s][l]) worlds.push_back(tree_matrix_[i]);
      const std::size_t before = stats.primitives;
      append(scene, o.full_detail ? full_[s] : levels_.at(s).at(l), worlds, stats.primitives);
      stats.species_primitives[s][l] += stats.primitives - before;
    }
  // Last of the opaque draws: where trees stand, the ground fails the depth test.
  if (o.ground && !ground_->meshes.empty()) append(scene, ground_, {Mat4::Identity()}, stats.primitives);
  return scene;
}

std::vector<Scene> ForestView::prepare_scenes(Renderer& renderer, std::span<const Camera> cameras,
                                              const RenderOptions& options, const ForestViewOptions& view,
                                              std::vector<ForestViewStats>& stats) const {
  // A view's scene names its levels' geometry and its atlases, which the renderer keeps: each
  // call uploads what the views before it did not use.
  const float aspect = float(options.width) / float(options.height);
  std::vector<Scene> scenes;
  stats.assign(cameras.size(), {});
  for (std::size_t i = 0; i < cameras.size(); ++i) {
    scenes.push_back(view_scene(cameras[i], aspect, view, stats[i]));
    renderer.prepare(scenes.back(), options);
  }
  return scenes;
}

void ForestView::prepare(Renderer& renderer, std::span<const Camera> cameras, const RenderOptions& options,
                         const ForestViewOptions& view) const {
  std::vector<ForestViewStats> unused;
  prepare_scenes(renderer, cameras, options, view, unused);
}

std::vector<image::Image> ForestView::render(Renderer& renderer, std::span<const Camera> cameras,
                                             const RenderOptions& options, const ForestViewOptions& view,
                                             std::vector<ForestViewStats>* stats) {
  // Each view's scene is built once, and all are uploaded before the first is drawn.
  std::vector<ForestViewStats> st;
  const std::vector<Scene> scenes = prepare_scenes(renderer, cameras, options, view, st);
  std::vector<image::Image> out;
  for (std::size_t i = 0; i < cameras.size(); ++i)
    out.push_back(renderer.render(scenes[i], cameras[i], options));
  if (stats) *stats = std::move(st);
  return out;
}

std::vector<Camera> forest_cameras(const CameraSet& set, const Bounds& forest_bounds) {
  std::vector<Camera> out;
  const float aspect = float(set.width) / float(set.height);
  for (const CameraView& v : set.views) out.push_back(resolve(v, forest_bounds, aspect));
  return out;
}

}  // namespace sylva::render
