// Drawing a forest artifact (libs/forest/instances.h) with the scene renderer: per view, every
// tree's LOD level is picked by its distance, tiles and trees outside the view frustum are
// culled, and each (species, level) mesh is drawn instanced once over the trees that use it.
//
// Level choice (docs/lod-model.md): a level of spatial error epsilon is valid from its
// switch distance d = epsilon / (delta s(1)) on; a tree is drawn with the coarsest level whose
// switch distance is at most the distance from the eye to the tree's world box (0 inside it), so
// every surface of the level is at least its switch distance away, as `sylva lodcheck` proves
// it. The species' chain was built for a pixel error delta; a view may allow another delta'
// (ForestViewOptions::pixel_error_px): the switch distances then scale by delta / delta'.
// The impostor, when a species has one, is its last level: a (hemi-)octahedral impostor (the
// level's `octahedral` impostor.json) is drawn by the scene renderer with the reference impostor
// shader (Scene::impostors, instanced, in the trees' depth buffer), with as many parallax steps
// as the level's parallax table proves enough at the tree's distance (16 nearer than its first
// row); billboards are drawn as the level's mesh of cards like every other level.
//
// Frustum culling: a tile's box, then each tree's box, against the six planes of the view
// (Celba §4.6.3: "for every frustum plane an effective radius of bounding box is computed and
// intersection with sphere with size of effective radius is performed against frustum plane" —
// here the exact box-plane test, which never culls a visible box).
#pragma once

#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "libs/forest/instances.h"
#include "libs/render/camera.h"
#include "libs/render/renderer.h"
#include "libs/render/scene.h"

namespace sylva::render {

struct ForestViewOptions {
  double pixel_error_px = 0;  // delta' of the view; 0 = each species' own chain delta
  bool full_detail = false;   // draw every tree with the full-detail model (set_full_detail), no LOD
  bool cull = true;           // frustum culling (off: every tree is drawn)
  bool ground = true;         // draw the ground (off for coverage checks: it would cover every pixel)
};

struct ForestViewStats {
  std::size_t trees = 0, trees_drawn = 0, tiles_drawn = 0;
  std::size_t impostors = 0;  // trees drawn as (hemi-)octahedral impostors (in trees_drawn)
  std::size_t primitives =
      0;  // triangles + lines + points drawn (an impostor: its 2-triangle quad; the ground)
  std::vector<std::size_t> per_level;  // trees drawn at each level index (full detail: index 0)
  // [species][level]: trees drawn and primitives drawn (full detail: level 0 only).
  std::vector<std::vector<std::size_t>> species_trees, species_primitives;
  // Octahedral impostors drawn with each number of parallax steps (the level's parallax table).
  std::map<int, std::size_t> impostor_steps;
};

class ForestView {
 public:
  // Loads instances.json (+ .bin), every species level glTF beside it and the (hemi-)octahedral
  // impostors' impostor.json and maps. Throws forest::FormatError, SceneLoadError,
  // impostor::ImpostorFormatError, image::ImageError or RenderError (one line, naming the file).
  static ForestView load(const std::filesystem::path& instances_json);
  // The levels' (and set_full_detail's) coincident blended lines are drawn merged
  // (merge_line_copies, line_merge.h): a third of a LOD level's lines; a pixel differs from
  // drawing every copy by a level or two of 255 per line over it (docs/renderer.md).
  ForestView(forest::Forest forest, std::vector<std::vector<Scene>> levels);

  const forest::Forest& forest() const { return forest_; }
  // The ground (Forest::ground's mesh, forest frame), drawn in every view after the trees.
  void set_ground(Scene ground);
  // Species s's octahedral impostor, drawn for its last level instead of that level's mesh.
  void set_octahedral(std::size_t species, std::shared_ptr<const ImpostorAtlas> atlas);
  // The full-detail model of species s (object space), for ForestViewOptions::full_detail.
  void set_full_detail(std::size_t species, Scene scene);

  // The level species s's tree is drawn with at `distance` metres (the rule above).
  std::size_t level_for(std::size_t species, double distance, const ForestViewOptions& options) const;
  // The parallax steps species s's octahedral impostor is drawn with at `distance` metres: the
  // last row of its level's parallax table whose distance (scaled like the switch distances) is
  // at most `distance`, else the reference shader's 16.
  int parallax_steps_for(std::size_t species, double distance, const ForestViewOptions& options) const;

  // Uploads everything the cameras' views draw (the target, every (species, level) mesh one of
  // them picks, its impostor maps) into `renderer` without drawing (Renderer::prepare): a
  // forest's loading step, after which each view's time is its drawing. render() starts with it.
  void prepare(Renderer& renderer, std::span<const Camera> cameras, const RenderOptions& options,
               const ForestViewOptions& view = {}) const;

  // Renders each camera (its own LOD selection and culling), one image per camera, after
  // prepare() for all of them.
  std::vector<image::Image> render(Renderer& renderer, std::span<const Camera> cameras,
                                   const RenderOptions& options, const ForestViewOptions& view = {},
                                   std::vector<ForestViewStats>* stats = nullptr);

  // World box of the whole forest (every tree's box and the ground).
  Bounds bounds() const;

  // The scene one view draws (what render() draws for `camera`): its LOD choice and culling,
  // with `stats` filled.
  Scene view_scene(const Camera& camera, float aspect, const ForestViewOptions& options,
                   ForestViewStats& stats) const;

 private:
  // Each camera's scene (its stats in `stats`), handed to renderer.prepare() as it is built.
  std::vector<Scene> prepare_scenes(Renderer& renderer, std::span<const Camera> cameras,
                                    const RenderOptions& options, const ForestViewOptions& view,
                                    std::vector<ForestViewStats>& stats) const;

  forest::Forest forest_;
  // The scenes are shared and never changed once stored (a setter stores a new one): every view's
  // meshes name them in Mesh::shared_geometry, so a renderer keeps their buffers uploaded.
  std::vector<std::vector<std::shared_ptr<const Scene>>> levels_;  // [species][level]
  std::vector<std::shared_ptr<const Scene>> full_;                 // [species], may be empty scenes
  std::vector<std::shared_ptr<const ImpostorAtlas>> octahedral_;   // [species], may be null
  std::vector<Bounds> tree_bounds_;                                // world box per instance
  std::vector<Mat4> tree_matrix_;                                  // world matrix per instance
  std::vector<Bounds> tile_bounds_;
  std::shared_ptr<const Scene> ground_;  // may be empty
};

// Cameras of a camera set for a forest: explicit eye/target views are used as they are; orbit
// views orbit the forest's box. z_near / z_far enclose the forest as seen from the eye.
std::vector<Camera> forest_cameras(const CameraSet& set, const Bounds& forest_bounds);

}  // namespace sylva::render
