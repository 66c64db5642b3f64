// Private: the GLSL sources of libs/render. Each is a file under libs/render/shaders/, compiled
// into the library byte for byte at build time (CMakeLists.txt reads every file into the
// generated shader_sources.cpp), so what the renderer compiles is what the repository holds.
//
// A file whose first line is `#version` is a whole shader but for the compile-time switches a
// program inserts after that line (with_prelude): #defines or constants that make each
// variant's code branch-free on llvmpipe. A `.glsl` file is such a prelude.
#pragma once

#include <string>
#include <string_view>

namespace sylva::render::detail {

// The reference (hemi-)octahedral impostor shader, shipped for engines (docs/stages/impostor.md;
// impostor_renderer.h gives it out, impostor_draw.h specialises it).
extern const char kOctahedralImpostorVert[];
extern const char kOctahedralImpostorFrag[];

// The scene renderer's shader (scene_programs.h). kSceneDrawStateGlsl is a printf format of the
// fragment shader's draw state, the constants u_has_texture ... u_line_copies (%s: true or false;
// %d: the alpha mode, 0 opaque, 1 mask, 2 blend), inserted after kSceneFrag's #version line.
extern const char kSceneVert[];
extern const char kSceneFrag[];
extern const char kSceneDrawStateGlsl[];

// Full-screen passes between render targets (render_target.h): one triangle covering the
// viewport (drawn with 3 vertices and no attributes).
extern const char kFullscreenVert[];
// One output pixel from the u_k x u_k texels of its block of u_source. The reduction is the
// prelude's START, COMBINE(a, b) and FINISH(a): kBlockMeanGlsl, the mean (supersampling's
// downsample), or kBlockMaxGlsl, the maximum (per pixel the farthest depth of its sub-pixels,
// the impostor shader's SYLVA_SCENE_DEPTH).
extern const char kBlockReduceFrag[];
extern const char kBlockMeanGlsl[];
extern const char kBlockMaxGlsl[];
// Hybrid antialiasing (supersample k with msaa k^2): sample s of a pixel of the multisampled
// target is sub-pixel u_sub of its k x k block of the supersampled one. kToSamplesFrag copies
// colour and depth of one sub-pixel to its sample (one pass per sample, glSampleMaski);
// kFromSamplesFrag copies the colour back (u_sample_of: sample index of sub-pixel x + k y).
extern const char kToSamplesFrag[];
extern const char kFromSamplesFrag[];

// The impostor bake (bake_programs.h): one program per variant, whose switches MERGED_LINES,
// HAS_NORMALS, HAS_COLORS, HAS_TEXTURE, OPAQUE_LAYER and IS_LINES are #defined 0 or 1 after the
// #version line of both.
extern const char kBakeVert[];
extern const char kBakeFrag[];

// `source` with `prelude` inserted after its first line, which must be a #version line; else
// throws RenderError("the <what> shader does not start with a #version line").
std::string with_prelude(std::string_view source, std::string_view prelude, std::string_view what);

}  // namespace sylva::render::detail
