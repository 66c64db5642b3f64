// Private: where the scene renderer draws a view (gl_renderer.cpp), the full-screen passes
// between its targets, and the read-back. Every function expects the context current.
//
// Without supersampling the view is drawn into draw_fbo (msaa samples) and resolved into
// resolve_fbo. Supersampled by k: draw_fbo is k times the size, one sample per pixel, averaged
// into output_fbo (a full-screen pass, shaders/block_reduce.frag with block_mean.glsl); with
// msaa = k^2 as well ("hybrid", docs/renderer.md "Supersampling"), impostors are drawn into
// samples_fbo, whose k^2 samples per pixel are the k x k sub-pixels of draw_fbo (sample_of).
#pragma once

#include <memory>
#include <vector>

#include "libs/image/image.h"
#include "libs/render/gl_util.h"
#include "libs/render/renderer.h"

namespace sylva::render::detail {

struct RenderTarget {
  int width = 0, height = 0;    // of draw_fbo: k x the output's
  GLuint draw_fbo = 0;          // multisampled when msaa > 1 and not supersampled
  GLuint resolve_fbo = 0;       // single-sampled; == draw_fbo when msaa == 1 or supersampled
  GLuint color_texture = 0;     // draw_fbo's colour when supersampled
  GLuint depth_texture = 0;     // draw_fbo's depth when hybrid
  GLuint output_fbo = 0;        // the output size; == resolve_fbo when not supersampled
  GLuint samples_fbo = 0;       // hybrid: output size, k^2 samples
  GLuint samples_texture = 0;   // its colour
  GLuint farthest_fbo = 0;      // hybrid: output size, R32F colour farthest_texture:
  GLuint farthest_texture = 0;  // per pixel the greatest depth of its sub-pixels
  std::vector<int> sample_of;   // hybrid: sample index of sub-pixel x + k y
  GLuint empty_vao = 0;         // for the full-screen passes
};

// Supersampled with msaa = supersample^2: impostors drawn multisampled over supersampled meshes.
inline bool hybrid(const RenderOptions& o) { return o.supersample > 1 && o.msaa > 1; }

// The target of the last call, kept for the next one of the same size, samples and
// supersampling (every pass of a view overwrites all of it).
class KeptTarget {
 public:
  // The target for `o` (made unless the kept one fits). Throws RenderError when the device cannot
  // make a framebuffer of it.
  const RenderTarget& for_options(const RenderOptions& o);
  // Deletes the kept target's GL names.
  void reset() { gl_.reset(); }

 private:
  std::unique_ptr<GlObjects> gl_;
  RenderTarget target_;
  int width_ = 0, height_ = 0, msaa_ = 0, supersample_ = 0;
};

// The full-screen passes between a target's framebuffers and the read-back.
class TargetPasses {
 public:
  // Links the passes' programs (RenderUnavailableError when the device cannot compile them).
  void link();
  void destroy();

  // Hybrid: per output pixel the greatest depth of its sub-pixels, into farthest_texture (the
  // impostor shader's SYLVA_SCENE_DEPTH).
  void farthest_depth(const RenderTarget& t, const RenderOptions& o) const;
  // Hybrid: the supersampled colour and depth into the multisampled target (sample s of a pixel =
  // its sub-pixel), ready for the impostors; bound, with its viewport.
  void to_samples(const RenderTarget& t, const RenderOptions& o) const;
  // ... and the samples' colour back into the supersampled target (its depth is unchanged:
  // impostors do not write depth); draw_fbo bound again with its viewport and depth test.
  void from_samples(const RenderTarget& t, const RenderOptions& o) const;
  // The view drawn into `t`: resolved (or downsampled), read back top row first, straight alpha.
  image::Image read_back(const RenderTarget& t, const RenderOptions& o) const;

 private:
  void output_pass(const RenderTarget& t, const RenderOptions& o, GLuint fbo, GLuint program,
                   GLuint texture) const;

  GLuint downsample_ = 0, to_samples_ = 0, farthest_depth_ = 0, from_samples_ = 0;
};

}  // namespace sylva::render::detail
