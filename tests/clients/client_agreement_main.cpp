// sylva_client_agreement: the second renderer over every glTF file a recipe wrote.
//
//   sylva_client_agreement RECIPE_OUT_DIR REPORT_DIR
//
// RECIPE_OUT_DIR is out/<recipe name>/ (one directory per node). For every mesh (tree.glb, plain
// or Draco), every LOD chain (lod.gltf, MSFT_lod), every LOD level (lod<i>.gltf), every
// ribbons variant (lod<i>_ribbons.gltf), the impostors' cards, each pack's coarsest levels and a
// forest's fullest tile at three tile levels it renders the views of agreement.h ("tree", "crown")
// in sylva's renderer and in three.js (headless Chromium), compares them and prints one row per
// file and view; then it checks with three.js's MSFT_lod plugin which level each chain shows at
// the distances its lod.json names, and loads every pack GLB and every forest tile file, counting
// what three.js draws; then two negative controls made from the recipe's own files
// (leaves wound against their normals; black bark) must be caught. Images and agreement.json go
// to REPORT_DIR. Exit codes: 0 all agree; 1 some file, view or control disagreed (the rows say
// which client, file and view); 2 usage or unreadable outputs; 77 three.js/Chromium/node are
// not installed (ctest: skipped) -- unless SYLVA_REQUIRE_CLIENTS=1, then 1.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "libs/fileio/read_file.h"
#include "libs/forest/instances.h"
#include "libs/image/image_io.h"
#include "libs/lodchain/lod_chain.h"
#include "libs/pack/manifest.h"
#include "libs/render/gltf_scene.h"
#include "tests/clients/agreement.h"

namespace fs = std::filesystem;
using namespace sylva;
using clients::Kind;

namespace {

void write_all(const fs::path& p, const std::string& bytes) {
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), std::streamsize(bytes.size()));
}

// The JSON of a .glb or .gltf.
nlohmann::json gltf_json(const fs::path& p) {
  const std::string b = fileio::read_file(p);
  if (b.size() >= 20 && b.compare(0, 4, "glTF") == 0) {
    std::uint32_t len = 0;
    std::memcpy(&len, b.data() + 12, 4);
    return nlohmann::json::parse(b.substr(20, len));
  }
  return nlohmann::json::parse(b);
}

bool uses(const nlohmann::json& j, const std::string& ext) {
  for (const auto& e : j.value("extensionsUsed", nlohmann::json::array()))
    if (e == ext) return true;
  return false;
}

bool has_lines(const nlohmann::json& j) {
  for (const auto& m : j.value("meshes", nlohmann::json::array()))
    for (const auto& p : m["primitives"])
      if (p.value("mode", 4) == 1) return true;
  return false;
}

bool is_forest(const fs::path& node_dir) {
  return fs::exists(node_dir / "instances.json") && fs::exists(node_dir / "tileset.json");
}

std::string tile_stem(const forest::Tile& t) {
  return "tile_" + std::to_string(t.ix) + "_" + std::to_string(t.iz);
}

struct Subject {
  fs::path file;
  std::string label;  // node/file
  Kind kind;
};

// A file-name-safe form of "node/file.gltf": "node_file-gltf" (no '.', so no directory named
// like a glTF file).
std::string slug(const std::string& label) {
  std::string s = label;
  std::replace(s.begin(), s.end(), '/', '_');
  std::replace(s.begin(), s.end(), '.', '-');
  return s;
}

// The recipe's glTF files, in node order.
std::vector<Subject> subjects(const fs::path& out_dir) {
  std::vector<fs::path> nodes;
  for (const auto& e : fs::directory_iterator(out_dir))
    if (e.is_directory() && e.path().filename().string()[0] != '.') nodes.push_back(e.path());
  std::sort(nodes.begin(), nodes.end());
  std::vector<Subject> out;
  for (const fs::path& n : nodes) {
    const std::string node = n.filename().string();
    if (fs::exists(n / "tree.glb")) {
      const bool draco = uses(gltf_json(n / "tree.glb"), "KHR_draco_mesh_compression");
      out.push_back({n / "tree.glb", node + "/tree.glb", draco ? Kind::kDracoMesh : Kind::kMesh});
    }
    if (fs::exists(n / "impostor.glb"))
      out.push_back({n / "impostor.glb", node + "/impostor.glb", Kind::kImpostor});
    if (fs::exists(n / "lod.json")) {
      const lodchain::LodChain summary = lodchain::read_lod_chain((n / "lod.json").string());
      out.push_back({n / "lod.gltf", node + "/lod.gltf", Kind::kChain});
      for (const lodchain::Level& l : summary.levels) {
        const std::string& f = l.file;
        out.push_back({n / f, node + "/" + f, has_lines(gltf_json(n / f)) ? Kind::kLineLevel : Kind::kLevel});
        if (l.ribbons_file)
          out.push_back({n / *l.ribbons_file, node + "/" + *l.ribbons_file, Kind::kRibbons});
      }
    }
    // An asset pack (stage pack): each species' coarsest mesh level file and its impostor level,
    // EXT_meshopt_compression (three.js decodes it with its MeshoptDecoder, sylva with
    // libs/render/meshopt_decode.h). Every pack file is also loaded and counted (pack_loads).
    if (fs::exists(n / "manifest.json")) {
      for (const auto& sp : pack::read_manifest(n / "manifest.json").species) {
        const std::size_t meshes = sp.levels.size() - (sp.impostor.empty() ? 0 : 1);
        const std::string f = sp.levels[meshes - 1].file;
        out.push_back({n / f, node + "/" + f, has_lines(gltf_json(n / f)) ? Kind::kLineLevel : Kind::kLevel});
        if (!sp.impostor.empty()) out.push_back({n / sp.impostor, node + "/" + sp.impostor, Kind::kImpostor});
      }
    }
    // A forest (stage forest, or a pack's copy of one): the tile with the most trees at its
    // first, middle and last tile level (full detail; bark lines; the impostors' cards).
    if (is_forest(n)) {
      const forest::Forest f = forest::read_instances(n / "instances.json");
      const forest::Tile* most = nullptr;
      for (const forest::Tile& t : f.tiles)
        if (!most || t.instances.size() > most->instances.size()) most = &t;
      std::size_t levels = 0;
      for (const forest::Species& sp : f.species) levels = std::max(levels, sp.levels.size());
      if (most && levels > 0) {
        std::vector<std::size_t> picked{0, levels / 2, levels - 1};
        picked.erase(std::unique(picked.begin(), picked.end()), picked.end());
        for (std::size_t l : picked) {
          const std::string f2 = tile_stem(*most) + "_lod" + std::to_string(l) + ".gltf";
          out.push_back({n / f2, node + "/" + f2, Kind::kForestTile});
        }
      }
    }
  }
  return out;
}

// A copy of level file `src` in `dir` with one defect: "mis-wound" swaps two corners of every
// leaf triangle (leaves wound against their normals, issue 10 finding 1); "black-bark" sets the
// bark colour to black (finding 2). Returns the copy's path or empty when `src` has no such part.
fs::path make_control(const fs::path& src, const fs::path& dir, const std::string& defect) {
  nlohmann::json j = nlohmann::json::parse(fileio::read_file(src));
  fs::create_directories(dir);
  bool changed = false;
  std::vector<std::string> bins;
  for (const auto& b : j["buffers"])
    bins.push_back(fileio::read_file(src.parent_path() / b["uri"].get<std::string>()));
  for (const auto& m : j["meshes"])
    for (const auto& p : m["primitives"]) {
      const std::string mat = j["materials"][p["material"].get<int>()]["name"];
      if (defect == "mis-wound" && mat == "leaves") {
        const auto& acc = j["accessors"][p["indices"].get<int>()];
        const auto& view = j["bufferViews"][acc["bufferView"].get<int>()];
        std::string& bin = bins[view["buffer"].get<std::size_t>()];
        const std::size_t size = acc["componentType"] == 5123 ? 2 : 4;
        const std::size_t off =
            view.value("byteOffset", std::size_t(0)) + acc.value("byteOffset", std::size_t(0));
        for (std::size_t t = 0; t + 3 <= acc["count"].get<std::size_t>(); t += 3)
          std::swap_ranges(bin.begin() + std::ptrdiff_t(off + (t + 1) * size),
                           bin.begin() + std::ptrdiff_t(off + (t + 2) * size),
                           bin.begin() + std::ptrdiff_t(off + (t + 2) * size));
        changed = true;
      }
    }
  if (defect == "black-bark")
    for (auto& m : j["materials"])
      if (m["name"] == "bark") {
        m["pbrMetallicRoughness"]["baseColorFactor"] = {0, 0, 0, 1};
        changed = true;
      }
  if (!changed) return {};
  for (std::size_t b = 0; b < bins.size(); ++b)
    write_all(dir / j["buffers"][b]["uri"].get<std::string>(), bins[b]);
  for (const auto& im : j.value("images", nlohmann::json::array()))
    fs::copy_file(src.parent_path() / im["uri"].get<std::string>(), dir / im["uri"].get<std::string>(),
                  fs::copy_options::overwrite_existing);
  const fs::path out = dir / src.filename();
  write_all(out, j.dump(2));
  return out;
}

// Files three.js only loads and counts. Every GLB of every pack under out_dir: each species' chain
// (with the MSFT_lod plugin) and each level file, with the primitives the pack's lod.json says
// each level has. Every tile file of every forest (and a pack's copy of one): the triangles and
// lines sylva's renderer draws for it, every instance counted.
struct Load {
  clients::LoadCheck check;
  std::string label;
  nlohmann::json expected;  // [{triangles, lines}] per level
  const char* source;       // where `expected` comes from: "lod.json" or "sylva"
};
std::vector<Load> forest_loads(const fs::path& out_dir) {
  std::vector<Load> out;
  std::vector<fs::path> nodes;
  for (const auto& e : fs::directory_iterator(out_dir))
    if (e.is_directory() && is_forest(e.path())) nodes.push_back(e.path());
  std::sort(nodes.begin(), nodes.end());
  for (const fs::path& n : nodes) {
    const forest::Forest f = forest::read_instances(n / "instances.json");
    std::size_t levels = 0;
    for (const forest::Species& sp : f.species) levels = std::max(levels, sp.levels.size());
    for (const forest::Tile& t : f.tiles)
      for (std::size_t l = 0; l < levels; ++l) {
        const std::string file = tile_stem(t) + "_lod" + std::to_string(l) + ".gltf";
        const render::Scene scene = render::load_gltf_scene(n / file);
        out.push_back(
            {{n / file, false},
             n.filename().string() + "/" + file,
             nlohmann::json::array({{{"triangles", scene.triangle_count()}, {"lines", scene.line_count()}}}),
             "sylva"});
      }
  }
  return out;
}

std::vector<Load> pack_loads(const fs::path& out_dir) {
  std::vector<Load> out;
  std::vector<fs::path> nodes;
  for (const auto& e : fs::directory_iterator(out_dir))
    if (e.is_directory() && fs::exists(e.path() / "manifest.json")) nodes.push_back(e.path());
  std::sort(nodes.begin(), nodes.end());
  for (const fs::path& n : nodes)
    for (const auto& sp : pack::read_manifest(n / "manifest.json").species) {
      const nlohmann::json lod = nlohmann::json::parse(fileio::read_file(n / sp.lod_json));
      nlohmann::json all = nlohmann::json::array();
      for (const auto& l : lod["levels"])
        all.push_back({{"triangles", l["triangles"]}, {"lines", l["lines"]}});
      const std::string node = n.filename().string();
      out.push_back({{n / sp.chain, true}, node + "/" + sp.chain, all, "lod.json"});
      for (std::size_t i = 0; i < sp.levels.size() && i < all.size(); ++i)
        out.push_back({{n / sp.levels[i].file, false},
                       node + "/" + sp.levels[i].file,
                       nlohmann::json::array({all[i]}),
                       "lod.json"});
    }
  return out;
}

struct Rendered {
  Subject subject;
  std::vector<render::Camera> cameras;
  std::vector<fs::path> sylva_png, client_png;
};

// Step 1 for one file: sylva's pictures of the views of agreement.h into `report`, and the
// three.js jobs for the same cameras appended to `jobs`.
Rendered render_sylva(render::Renderer& renderer, const render::RenderOptions& options,
                      const fs::path& report, const Subject& s, std::vector<clients::ClientRender>& jobs) {
  Rendered r{s, {}, {}, {}};
  const render::Scene scene = render::load_gltf_scene(s.file);
  r.cameras = clients::views(scene.bounds());
  const std::vector<image::Image> images = renderer.render_views(scene, r.cameras, options);
  for (std::size_t v = 0; v < r.cameras.size(); ++v) {
    const std::string stem = slug(s.label) + "__" + r.cameras[v].name;
    r.sylva_png.push_back(report / (stem + "_sylva.png"));
    r.client_png.push_back(report / (stem + "_threejs.png"));
    image::write_png(images[v], r.sylva_png.back());
    jobs.push_back({s.file, r.client_png.back(), r.cameras[v]});
  }
  return r;
}

// A negative control: three.js draws the broken copy `file` of rendered[good].
struct Control {
  std::string defect;
  std::size_t good;  // index into rendered
  fs::path file;
  std::vector<fs::path> client_png, sylva_bad_png;
};

// Foliage elements (leaves, needle lines and quads) of level 2 of the chain beside `s`; -1 when
// the chain has fewer than 3 levels.
long foliage_at_level2(const Subject& s) {
  const lodchain::LodChain j = lodchain::read_lod_chain((s.file.parent_path() / "lod.json").string());
  if (j.levels.size() < 3) return -1;
  const lodchain::LevelCounts& c = j.levels[2].counts;
  return long(c.leaves + c.needle_lines + c.needle_quads);
}

long leaves_at_level2(const Subject& s) {
  const lodchain::LodChain j = lodchain::read_lod_chain((s.file.parent_path() / "lod.json").string());
  return j.levels.size() < 3 ? -1 : long(j.levels[2].counts.leaves);
}

// The controls' subjects, as indices into `rendered` (rendered.size() for none): level 2 of the
// chain with the most leaves there (mis-wound), and of the chain with the least foliage there
// (black bark: bark is most of its picture).
std::pair<std::size_t, std::size_t> control_subjects(const std::vector<Rendered>& rendered) {
  std::size_t most = rendered.size(), least = rendered.size();
  long most_n = -1, least_n = -1;
  for (std::size_t i = 0; i < rendered.size(); ++i) {
    const Subject& s = rendered[i].subject;
    if ((s.kind != Kind::kLevel && s.kind != Kind::kLineLevel) ||
        s.label.find("/lod2.gltf") == std::string::npos)
      continue;
    const long n = foliage_at_level2(s), leaves = leaves_at_level2(s);
    if (n < 0) continue;
    if (leaves > 0 && (most_n < 0 || leaves > most_n)) most = i, most_n = leaves;
    if (least_n < 0 || n < least_n) least = i, least_n = n;
  }
  return {most, least};
}

// Step 2: negative controls from the recipe's own files: a level with leaves, mis-wound; a level,
// black bark. three.js draws the broken copy (jobs appended to `jobs`); sylva draws the original
// the verifier approved, and the broken copy too.
std::vector<Control> make_controls(render::Renderer& renderer, const render::RenderOptions& options,
                                   const fs::path& report, const std::vector<Rendered>& rendered,
                                   std::vector<clients::ClientRender>& jobs) {
  const auto [most, least] = control_subjects(rendered);
  std::vector<Control> controls;
  for (const std::string defect : {"mis-wound", "black-bark"})
    for (std::size_t i = 0; i < rendered.size(); ++i) {
      const Subject& s = rendered[i].subject;
      if (i != (defect == "mis-wound" ? most : least)) continue;
      const fs::path copy =
          make_control(s.file, report / "controls" / (defect + "_" + slug(s.label)), defect);
      if (copy.empty()) continue;
      Control c{defect, i, copy, {}, {}};
      const render::Scene bad = render::load_gltf_scene(copy);
      const std::vector<image::Image> imgs = renderer.render_views(bad, rendered[i].cameras, options);
      for (std::size_t v = 0; v < rendered[i].cameras.size(); ++v) {
        const std::string stem =
            "control_" + defect + "_" + slug(s.label) + "__" + rendered[i].cameras[v].name;
        c.client_png.push_back(report / (stem + "_threejs.png"));
        c.sylva_bad_png.push_back(report / (stem + "_sylva.png"));
        image::write_png(imgs[v], c.sylva_bad_png.back());
        jobs.push_back({copy, c.client_png.back(), rendered[i].cameras[v]});
      }
      controls.push_back(std::move(c));
      break;
    }
  return controls;
}

// A chain whose MSFT_lod levels three.js's plugin shows at `distances`.
struct Chain {
  std::string node;
  lodchain::LodChain summary;
  std::vector<double> distances;
};

// Step 3: every chain, with the distances to look at it from: just past each switch distance of
// lod.json, and just before and after each distance where the coverages make a loader switch.
// The plugin's checks are appended to `lod_checks`, one per chain.
std::vector<Chain> lod_chains(const std::vector<Subject>& files, std::vector<clients::LodCheck>& lod_checks) {
  std::vector<Chain> chains;
  for (const Subject& s : files) {
    if (s.kind != Kind::kChain) continue;
    Chain c{s.label.substr(0, s.label.find('/')),
            lodchain::read_lod_chain((s.file.parent_path() / "lod.json").string()),
            {}};
    for (const lodchain::Level& l : c.summary.levels) {
      c.distances.push_back(std::max(0.01, l.switch_distance_m) * 1.001);
      if (l.coverage_switch_distance_m) {
        c.distances.push_back(*l.coverage_switch_distance_m * 0.999);
        c.distances.push_back(*l.coverage_switch_distance_m * 1.001);
      }
    }
    lod_checks.push_back({s.file, c.summary.camera_fov_y_deg, c.summary.bounding_radius_m, c.distances});
    chains.push_back(std::move(c));
  }
  return chains;
}

// Step 5: the table, one row per file and view, each into `table`. True when every row passes.
bool compare_renders(const std::vector<Rendered>& rendered, nlohmann::json& table) {
  bool all_ok = true;
  std::printf("%-9s %-32s %-6s %-15s %-23s %-22s\n", "client", "file", "view", "kind",
              "silhouette IoU >= bound", "mean colour <= bound");
  for (const Rendered& r : rendered)
    for (std::size_t v = 0; v < r.cameras.size(); ++v) {
      clients::Row row;
      row.file = r.subject.label;
      row.view = r.cameras[v].name;
      row.kind = r.subject.kind;
      row.bound = clients::bound_for(row.kind);
      row.a = clients::compare(image::read_image(r.sylva_png[v]), image::read_image(r.client_png[v]));
      std::printf("%s\n", row.line().c_str());
      all_ok &= row.passed();
      table.push_back({{"client", row.client},
                       {"file", row.file},
                       {"view", row.view},
                       {"kind", clients::kind_name(row.kind)},
                       {"iou", row.a.iou},
                       {"colour", row.a.colour},
                       {"min_iou", row.bound.min_iou},
                       {"max_colour", row.bound.max_colour},
                       {"passed", row.passed()}});
    }
  return all_ok;
}

// Step 6: the controls must be caught: three.js's picture of the broken file against sylva's of
// the approved file disagrees; sylva's own picture of the broken file shows the defect too (the
// verifier's reference images would flag it), and agrees with three.js's. Rows into `rows`; true
// when both controls were made and caught.
bool check_controls(const std::vector<Rendered>& rendered, const std::vector<Control>& controls,
                    nlohmann::json& rows) {
  bool all_ok = true;
  std::printf(
      "\nnegative controls (some view must DISAGREE with the approved picture, and sylva must see it "
      "there):\n");
  for (const Control& c : controls) {
    const Rendered& good = rendered[c.good];
    bool control_caught = false;
    for (std::size_t v = 0; v < good.cameras.size(); ++v) {
      clients::Row row;
      row.file = "controls/" + c.defect + " " + good.subject.label;
      row.view = good.cameras[v].name;
      row.kind = good.subject.kind;
      row.bound = clients::bound_for(row.kind);
      const image::Image client = image::read_image(c.client_png[v]);
      row.a = clients::compare(image::read_image(good.sylva_png[v]), client);
      // sylva's own picture of the broken file against the approved one: the verifier's reference
      // comparison sees the defect too (the renderer follows glTF's two-sided rule).
      const clients::Agreement same =
          clients::compare(image::read_image(good.sylva_png[v]), image::read_image(c.sylva_bad_png[v]));
      const bool caught = !row.passed();
      const bool sylva_sees_it = !(same.iou >= row.bound.min_iou && same.colour <= row.bound.max_colour);
      std::printf("%s  -> %s; sylva broken vs approved: IoU %.3f colour %.2f (%s)\n", row.line().c_str(),
                  caught ? "caught" : "NOT CAUGHT", same.iou, same.colour,
                  sylva_sees_it ? "sylva's verifier sees it too" : "SYLVA DOES NOT SEE IT");
      control_caught |= caught && sylva_sees_it;
      rows.push_back({{"defect", c.defect},
                      {"file", good.subject.label},
                      {"view", row.view},
                      {"iou", row.a.iou},
                      {"colour", row.a.colour},
                      {"caught", caught},
                      {"sylva_iou", same.iou},
                      {"sylva_colour", same.colour}});
    }
    std::printf("  %s control on %s: %s\n", c.defect.c_str(), good.subject.label.c_str(),
                control_caught ? "caught (three.js disagrees with the approved picture)" : "NOT CAUGHT");
    all_ok &= control_caught;
  }
  if (controls.size() < 2) {
    std::printf("NOT CHECKED: the recipe has no lod2 level with leaves and with bark for both controls\n");
    all_ok = false;
  }
  return all_ok;
}

// Step 7 at each of the chain's distances: the level the plugin shows (`got`) is the finest level
// whose coverage distance is beyond it, and no coarser than lod.json allows there. Rows into `rows`.
bool check_lod_distances(const Chain& c, const nlohmann::json& got, nlohmann::json& rows) {
  bool all_ok = true;
  const std::vector<lodchain::Level>& levels = c.summary.levels;
  for (std::size_t t = 0; t < c.distances.size(); ++t) {
    const double d = c.distances[t];
    const int shown = got["shown"][t];
    // Predicted by the coverages: the finest level whose coverage distance is beyond d.
    int predicted = 0;
    for (std::size_t i = 0; i + 1 < levels.size(); ++i)
      if (levels[i].coverage_switch_distance_m && d >= *levels[i].coverage_switch_distance_m)
        predicted = int(i) + 1;
    // The coarsest level lod.json allows at d.
    int allowed = 0;
    for (std::size_t i = 0; i < levels.size(); ++i)
      if (levels[i].switch_distance_m <= d) allowed = int(i);
    const bool ok = shown == predicted && shown <= allowed;
    std::printf("  d %9.3f m  shows level %d (coverages predict %d; lod.json allows up to %d)  %s\n", d,
                shown, predicted, allowed, ok ? "ok" : "WRONG");
    all_ok &= ok;
    rows.push_back({{"node", c.node},
                    {"distance_m", d},
                    {"shown", shown},
                    {"predicted", predicted},
                    {"allowed", allowed}});
  }
  return all_ok;
}

// Step 7 at each level's switch distance (+0.1 %): the plugin shows that level, or -- where the
// coverage before it was clamped at 1 -- a finer one.
bool check_lod_levels(const Chain& c, const nlohmann::json& got) {
  bool all_ok = true;
  const std::vector<lodchain::Level>& levels = c.summary.levels;
  for (std::size_t i = 0; i < levels.size(); ++i) {
    const double d = levels[i].switch_distance_m;
    int shown = -1;
    for (std::size_t t = 0; t < c.distances.size(); ++t)
      if (std::abs(c.distances[t] - std::max(0.01, d) * 1.001) < 1e-12) shown = got["shown"][t];
    const bool clamped = i > 0 && levels[i - 1].screen_coverage >= 1.0;
    std::printf(
        "  level %zu: lod.json switch distance %.3f m, coverage %.5f: three.js shows level %d there%s\n", i,
        d, levels[i].screen_coverage, shown,
        shown == int(i) ? ""
        : clamped       ? " (finer: the coverage before it is clamped at 1)"
                        : "  WRONG");
    if (shown != int(i) && !clamped) all_ok = false;
  }
  return all_ok;
}

// Step 7: MSFT_lod in three.js (plugin three-gltf-extensions, calculateDistance = the inverse of
// lod_gltf.h's coverage): never a coarser level than lod.json allows at a distance, and exactly
// the level the coverages predict. `result` is three.js's result.
bool check_msft_lod(const std::vector<Chain>& chains, const nlohmann::json& result, nlohmann::json& rows) {
  bool all_ok = true;
  std::printf("\nMSFT_lod in three.js (three-gltf-extensions), level shown at a distance:\n");
  for (std::size_t k = 0; k < chains.size(); ++k) {
    const Chain& c = chains[k];
    const nlohmann::json& got = result["lod_checks"][k];
    std::printf("%s: %zu levels in the plugin\n", c.node.c_str(), got["levels"].get<std::size_t>());
    all_ok &= check_lod_distances(c, got, rows);
    all_ok &= check_lod_levels(c, got);
  }
  return all_ok;
}

// Step 8: every pack GLB loads in three.js and draws the primitives its lod.json names: the
// chain's MSFT_lod levels (the impostor last) one by one, and each level file. Every forest tile
// file draws in three.js the triangles and lines it draws in sylva, every instance (three.js
// instances only triangle meshes: a tile whose instanced mesh had lines would draw once).
bool check_loads(const std::vector<Load>& loads, const nlohmann::json& result, nlohmann::json& rows) {
  bool all_ok = true;
  if (!loads.empty()) std::printf("\npack and forest files in three.js (loaded, primitives counted):\n");
  for (std::size_t k = 0; k < loads.size(); ++k) {
    const nlohmann::json& got = result["load_checks"][k];
    const nlohmann::json& want = loads[k].expected;
    nlohmann::json levels = got.value("levels", nlohmann::json::array());
    bool ok = levels.size() == want.size();
    for (std::size_t i = 0; ok && i < want.size(); ++i)
      ok = levels[i]["triangles"] == want[i]["triangles"] && levels[i]["lines"] == want[i]["lines"];
    std::printf("  %-36s %zu level(s) (%s: %zu), primitives %s  %s\n", loads[k].label.c_str(), levels.size(),
                loads[k].source, want.size(), ok ? (std::string("as ") + loads[k].source).c_str() : "DIFFER",
                ok ? "ok" : "WRONG");
    if (!ok)
      std::printf("    three.js %s\n    %s %s\n", levels.dump().c_str(), loads[k].source,
                  want.dump().c_str());
    all_ok &= ok;
    rows.push_back({{"file", loads[k].label},
                    {"threejs", levels},
                    {"expected", want},
                    {"source", loads[k].source},
                    {"passed", ok}});
  }
  return all_ok;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: sylva_client_agreement RECIPE_OUT_DIR REPORT_DIR\n";
    return 2;
  }
  const fs::path out_dir = argv[1], report = argv[2];
  const char* req = std::getenv("SYLVA_REQUIRE_CLIENTS");
  const bool require = req && std::string(req) == "1";
  std::vector<Subject> files;
  std::vector<Load> loads;
  try {
    files = subjects(out_dir);
    loads = pack_loads(out_dir);
    for (Load& l : forest_loads(out_dir)) loads.push_back(std::move(l));
  } catch (const std::exception& e) {
    std::cerr << "sylva_client_agreement: " << out_dir.string() << ": " << e.what() << "\n";
    return 2;
  }
  if (files.empty()) {
    std::cerr << "sylva_client_agreement: no glTF outputs under " << out_dir.string() << "\n";
    return 2;
  }
  std::error_code ec;
  fs::remove_all(report, ec);
  fs::create_directories(report);
  std::unique_ptr<render::Renderer> renderer;
  try {
    renderer = render::Renderer::create_headless();
  } catch (const render::RenderError& e) {
    std::cerr << "sylva_client_agreement: " << e.what() << "\n";
    return 1;
  }
  const render::RenderOptions options = clients::render_options();

  // 1. sylva's renders, and the three.js jobs for the same cameras.
  std::vector<Rendered> rendered;
  std::vector<clients::ClientRender> jobs;
  try {
    for (const Subject& s : files) rendered.push_back(render_sylva(*renderer, options, report, s, jobs));
  } catch (const std::exception& e) {
    std::cerr << "sylva_client_agreement: " << e.what() << "\n";
    return 2;
  }

  // 2. Negative controls from the recipe's own files.
  const std::vector<Control> controls = make_controls(*renderer, options, report, rendered, jobs);

  // 3. MSFT_lod plugin: the distances to look at each chain from.
  std::vector<clients::LodCheck> lod_checks;
  const std::vector<Chain> chains = lod_chains(files, lod_checks);

  // 4. three.js, all at once (one browser).
  std::vector<clients::LoadCheck> load_checks;
  for (const Load& l : loads) load_checks.push_back(l.check);
  const clients::ClientResult cr = clients::run_threejs(jobs, lod_checks, report / "work", load_checks);
  if (cr.unavailable) {
    std::cout << "three.js is not available: " << cr.message;
    return require ? 1 : 77;
  }
  if (!cr.ok) {
    std::cerr << "three.js failed: " << cr.message;
    return 1;
  }
  std::cout << "sylva:    " << renderer->device_description()
            << "\nthree.js: " << cr.result["renderer"].get<std::string>() << "\n\n";

  // 5.-8. The table, the controls, MSFT_lod and the loads, each printed; then agreement.json.
  nlohmann::json table = nlohmann::json::array(), control_rows = nlohmann::json::array(),
                 lod_rows = nlohmann::json::array(), load_rows = nlohmann::json::array();
  bool all_ok = compare_renders(rendered, table);
  all_ok &= check_controls(rendered, controls, control_rows);
  all_ok &= check_msft_lod(chains, cr.result, lod_rows);
  all_ok &= check_loads(loads, cr.result, load_rows);
  std::ofstream(report / "agreement.json")
      << nlohmann::json{{"rows", table}, {"controls", control_rows}, {"lod", lod_rows}, {"loads", load_rows}}
             .dump(2)
      << "\n";
  std::printf("\n%s; images in %s\n", all_ok ? "every client agrees" : "DISAGREEMENT (rows above)",
              report.string().c_str());
  return all_ok ? 0 : 1;
}
