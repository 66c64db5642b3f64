// impostor.json: what an `impostor` artifact is, for every program that reads one (the stage
// writes it; `sylva impostorcheck`, libs/render's impostor drawing, engines read it). The one
// reader and writer of the format (docs/formats.md, docs/stages/impostor.md "impostor.json").
//
// Contract: write_impostor_json(info) gives deterministic bytes (fixed key order, numbers as
// nlohmann::json prints doubles: shortest round-trip); parse_impostor_json(write(x)) == x.
// parse_impostor_json checks every field's presence, type and range and throws
// ImpostorFormatError("<source>: error: <what>") on the first problem; it never crashes on bad
// input. The camera fov round-trips through degrees (to within one ulp). Units: metres, radians only where a
// name says _rad (angles in the file are degrees, named _deg); object space is glTF's (Y up, right-handed,
// azimuth 0 = from +Z).
#pragma once

#include <array>
#include <stdexcept>
#include <string>
#include <vector>

#include "libs/impostor/error_model.h"

namespace sylva::impostor {

// The impostor artifact's files that other programs look for by name (docs/stages/impostor.md).
inline constexpr const char* kImpostorJsonFile = "impostor.json";  // this format
inline constexpr const char* kImpostorGlbFile = "impostor.glb";    // the cards every client draws

class ImpostorFormatError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

enum class Kind { kHemiOctahedral, kOctahedral, kBillboards };
const char* kind_name(Kind k);  // "hemi_octahedral", "octahedral", "billboards"

using Vec3d = std::array<double, 3>;
using Vec2d = std::array<double, 2>;

// One card of impostor.glb (billboards; or the cross of frames the octahedral kinds write as a
// fallback for viewers without the impostor shader). A card is a rectangle in object space,
// centre + [-half_width, half_width] right + [-half_height, half_height] up, facing `dir`, that
// shows the atlas rectangle [x, x + w) x [y, y + h) (pixels, top-left origin) of the frame baked
// from `dir`; `cutout` is the convex polygon (counter-clockwise seen from `dir`, 4..8 vertices,
// in frame uv: (0,0) top-left, (1,1) bottom-right of the rectangle) that the card's geometry is;
// `lower_cutout`, when not empty, a second convex polygon (3..16 vertices) below it, sharing no
// area with it: the card is split at a row so that a wide crown and a narrow trunk each get a
// tight polygon (stages/impostor/cutout.h says why).
struct Card {
  std::string name;
  Vec3d dir{}, right{}, up{}, center{};
  double half_width = 0, half_height = 0;
  int x = 0, y = 0, w = 0, h = 0;
  std::vector<Vec2d> cutout;
  std::vector<Vec2d> lower_cutout;
  friend bool operator==(const Card&, const Card&) = default;
};

struct ImpostorInfo {
  Kind kind = Kind::kHemiOctahedral;
  // Atlas. Octahedral kinds: frames_per_side^2 square frames of frame_px texels, frame (i, j) at
  // pixels [i F, (i+1) F) x [j F, (j+1) F). Billboards: one frame per card (Card::x..h).
  int frames_per_side = 0;
  int frame_px = 0;
  int atlas_width_px = 0, atlas_height_px = 0;
  int padding_px = 0;  // transparent border inside every frame, >= 2^mip_levels
  int mip_levels = 0;  // mip levels the padding keeps free of bleeding (sample with max level this)
  bool hemi = false;   // kind == kHemiOctahedral
  // Geometry (object space of the source asset).
  Vec3d bounds_min{}, bounds_max{};
  Vec3d sphere_center{};         // frames are centred here
  double sphere_radius = 0;      // every vertex is within this distance of the centre
  double frame_half_extent = 0;  // W: a frame spans [-W, W]^2 around the centre (= R F / (F - 2 padding))
  // Maps (PNG files beside impostor.json).
  std::string color_map;         // sRGB base colour (unlit albedo), straight alpha = coverage
  std::string normal_depth_map;  // RGB = object-space normal * 0.5 + 0.5, A = depth (see depth_encoding)
  // Error model and switch distance (error_model.h).
  lodmodel::Camera camera;
  double pixel_error_px = 0;  // delta
  ErrorTerms error;
  double switch_distance_m = 0;
  // What was baked.
  std::string source_type;  // "mesh" or "lod"
  std::string source_file;  // e.g. "lod3.glb"
  int source_level = -1;    // LOD level index, -1 for a mesh
  // The cards' glTF: its file name beside impostor.json (the impostor stage's impostor.glb; a
  // forest renames it with the species), its triangles and its cards.
  std::string glb_file = kImpostorGlbFile;
  std::vector<Card> cards;
  std::size_t glb_triangles = 0;
  friend bool operator==(const ImpostorInfo&, const ImpostorInfo&) = default;
};

// The fixed texts impostor.json carries so that a reader needs nothing else.
extern const char* const kFrameDirectionFormula;  // the grid's frame directions and blending
extern const char* const kDepthEncoding;          // normal map alpha

std::string write_impostor_json(const ImpostorInfo& info);
ImpostorInfo parse_impostor_json(const std::string& text, const std::string& source_name);
ImpostorInfo read_impostor_json(const std::string& path);  // also throws for an unreadable file

}  // namespace sylva::impostor
