#version 330 core
// sylva's reference fragment shader for (hemi-)octahedral impostors: per frame, march the view
// ray through the frame's depth map to the first surface it stored (relief mapping: Policarpo,
// Oliveira & Comba 2005; parallax occlusion mapping: Tatarchuk 2006), sample there; blend the
// three frames by their weights; light like sylva's renderer.
// docs/stages/impostor.md explains every uniform and formula. Public domain (CC0).

in vec3 v_obj;
flat in vec3 v_eye_obj;
flat in vec3 v_dir[3];
flat in vec3 v_right[3];
flat in vec3 v_up[3];
flat in vec2 v_cell[3];
flat in vec3 v_weight;
flat in mat3 v_normal_matrix;

// Both maps are uploaded premultiplied by coverage (the PNGs are straight): texture filtering
// and mip levels then weight every texel by what it covers. Filtering straight colours gives a
// texel that a twig covers by 5 % the same weight as a leaf texel beside it, so thin twigs' bark
// colour and lit normals would tint the whole crown.
uniform sampler2D u_color;         // atlas.color: sRGB texture (GL_SRGB8_ALPHA8) of linear rgb * a, a = coverage
uniform sampler2D u_normal_depth;  // atlas.normal_depth: linear RGBA8, rgb = (normal * 0.5 + 0.5) * coverage, a = depth
uniform int u_frames;              // N
uniform vec3 u_center;             // sphere.center
uniform float u_radius;            // sphere.radius_m, R
uniform float u_half_extent;       // frame_half_extent_m, W
uniform float u_padding;           // atlas.padding_px / atlas.frame_px
uniform float u_atlas_px;          // atlas.width_px (= frames_per_side * frame_px)
uniform int u_parallax_steps;      // ray-march steps through the depth range (16); 0 = flat frames
uniform vec3 u_ambient;            // linear RGB (sylva: 0.35)
uniform vec3 u_light_color;        // linear RGB (sylva: 0.75)
uniform vec3 u_light_dir;          // unit, world space, toward the light

out vec4 o_color;

// Frame uv (0,0 top-left .. 1,1) of an object-space point, then atlas uv, kept inside the frame's
// padding so no mip level up to atlas.mip_levels reads a neighbouring frame.
vec2 frame_uv(vec3 x, int k) {
  vec3 a = x - u_center;
  return vec2(0.5 + dot(a, v_right[k]) / (2.0 * u_half_extent), 0.5 - dot(a, v_up[k]) / (2.0 * u_half_extent));
}

vec2 atlas_uv(vec3 x, int k) {
  vec2 fuv = clamp(frame_uv(x, k), vec2(u_padding), vec2(1.0 - u_padding));
  return (v_cell[k] + fuv) / float(u_frames);
}

float to_srgb(float c) {
  c = clamp(c, 0.0, 1.0);
  return c <= 0.0031308 ? 12.92 * c : 1.055 * pow(c, 1.0 / 2.4) - 0.055;
}

#ifdef SYLVA_DEPTH_COVERAGE
// Optional, exact: the march's two unfiltered reads per step, the depth (u_normal_depth's alpha)
// and the coverage (u_color's alpha) of one texel, from one texture that holds both, texel for
// texel (RG8, level 0: r = depth, g = coverage). The same bytes, one fetch instead of two.
uniform sampler2D u_depth_coverage;
#endif

#ifdef SYLVA_EMPTY_DISTANCE
// Optional, exact: a fragment whose ray, in each of its three frames, reads only texels that
// store nothing (every byte 0) ends with albedo 0 and is discarded below; this finds most such
// fragments before the march. u_empty_distance (atlas_px / u_empty_cell_px square, R8, texelFetch)
// holds per cell of u_empty_cell_px x u_empty_cell_px texels a lower bound, in texels / 255, of
// the Chebyshev distance from any point of the cell to any texel of its frame that stores
// something. Every texel this shader reads for frame k lies at a frame point of the ray between
// the sphere's front and back (h = R .. -R: the march's samples, its crossings, the flat frame's
// plane point), clamped into the padding; a read at point x reaches texels within 1.5 texels of
// its upper mip level of x (GL: rho <= m_u + m_v, levels floor(log2 rho) and one above, at most
// mip_levels; the maps' mip levels are 2 x 2 boxes of the one below) and never another frame
// (the padding). Clamping moves no two points apart, so stepping along the ray's frame segment
// by (distance - reach) in the Chebyshev norm skips only points whose reads meet nothing.
uniform sampler2D u_empty_distance;
uniform int u_empty_cell_px;
uniform int u_mip_levels;  // atlas.mip_levels

// The empty distance (texels) at frame point p (texels) of frame k, p clamped as atlas_uv does.
float empty_distance(vec2 p, int k, float frame_px, float cells) {
  vec2 q = clamp(p, vec2(u_padding * frame_px), vec2((1.0 - u_padding) * frame_px));
  ivec2 cell = ivec2(clamp(floor(q / float(u_empty_cell_px)), vec2(0.0), vec2(cells - 1.0)));
  return texelFetch(u_empty_distance, ivec2(v_cell[k] * cells) + cell, 0).r * 255.0;
}

bool meets_stored_texels(vec3 ray, float rds[3], float h0s[3], vec2 dus[3], vec2 dvs[3]) {
  float frame_px = u_atlas_px / float(u_frames);
  float cells = frame_px / float(u_empty_cell_px);
  for (int k = 0; k < 3; ++k) {
    if (v_weight[k] <= 0.0) continue;  // adds 0 x its (finite) colour
    vec2 front = frame_uv(v_eye_obj + ray * ((u_radius - h0s[k]) / rds[k]), k) * frame_px;
    vec2 back = frame_uv(v_eye_obj + ray * ((-u_radius - h0s[k]) / rds[k]), k) * frame_px;
    vec2 seg = back - front;
    float seg_len = max(abs(seg.x), abs(seg.y));  // Chebyshev, texels
    float rho = (max(abs(dus[k].x), abs(dvs[k].x)) + max(abs(dus[k].y), abs(dvs[k].y))) * u_atlas_px * 1.05;
    float level = clamp(floor(log2(max(rho, 1.0))) + 1.0, 0.0, float(u_mip_levels));
    float reach = 1.5 * exp2(level) + 1.0;  // texels
    // First the middle, whose free distance covers the whole segment when it is at least half its
    // length; then, if it is free at all, steps from the front.
    float free = empty_distance(front + seg * 0.5, k, frame_px, cells) - reach;
    if (free >= 0.5 * seg_len) continue;
    if (free <= 0.0) return true;
    float s = 0.0;  // along the segment, 0 .. 1
    bool meets = true;
    for (int i = 0; i < 4; ++i) {
      free = empty_distance(front + seg * s, k, frame_px, cells) - reach;
      if (free <= 0.0) break;
      if (seg_len * (1.0 - s) <= free) {
        meets = false;
        break;
      }
      s += free / seg_len;
    }
    if (meets) return true;
  }
  return false;
}
#endif

#ifdef SYLVA_SCENE_DEPTH
// Optional, exact, for a multisampled target: a fragment all of whose samples fail the depth
// test (GL_LESS) adds nothing, so it is discarded before the march (llvmpipe runs a multisampled
// fragment's shader even when every sample failed its early depth test). u_scene_depth (target
// size, R32F, texelFetch) holds per pixel the greatest depth its samples hold. The samples lie
// within half a pixel of the centre in x and in y, so on the quad's plane their depths are
// >= the centre's less half its slope in x and in y; 2e-6 (~30 float steps of depth near 1)
// covers the rasteriser's own rounding of that plane.
uniform sampler2D u_scene_depth;

bool hidden_by_scene(float slope) {
  return texelFetch(u_scene_depth, ivec2(gl_FragCoord.xy), 0).r < gl_FragCoord.z - slope - 2e-6;
}
#endif

void main() {
  vec3 ray = normalize(v_obj - v_eye_obj);
  // Per frame: heights along the frame's direction, h(t) = h0 + t rd on the ray eye + t ray, and
  // the mip level's derivatives, from the point where the ray crosses the frame's plane (not
  // from the march's steps below).
  float rds[3], h0s[3];
  vec2 uv0s[3], dus[3], dvs[3];
  for (int k = 0; k < 3; ++k) {
    rds[k] = min(dot(ray, v_dir[k]), -1e-4);  // the ray runs against the frame's direction
    h0s[k] = dot(v_eye_obj - u_center, v_dir[k]);
    uv0s[k] = atlas_uv(v_eye_obj + ray * (-h0s[k] / rds[k]), k);
    dus[k] = dFdx(uv0s[k]);
    dvs[k] = dFdy(uv0s[k]);
  }
#ifdef SYLVA_SCENE_DEPTH
  if (hidden_by_scene(0.5 * (abs(dFdx(gl_FragCoord.z)) + abs(dFdy(gl_FragCoord.z))))) discard;
#endif
#ifdef SYLVA_EMPTY_DISTANCE
  if (!meets_stored_texels(ray, rds, h0s, dus, dvs)) discard;
#endif
  vec4 albedo = vec4(0.0);  // premultiplied, linear
  vec3 normal = vec3(0.0);
  for (int k = 0; k < 3; ++k) {
    float rd = rds[k], h0 = h0s[k];
    vec2 uv0 = uv0s[k], du = dus[k], dv = dvs[k];
    // March the ray from the front of the sphere (h = R) to its back (h = -R) and stop at the
    // first sample that lies below the height the frame stored there (relief / parallax
    // occlusion mapping on the depth map); uncovered texels store the back, so the ray passes them.
    // A texel covered less than half (alpha is the coverage of its whole column, so a twig line
    // alone in it has nothing behind it there) is seen through: the ray goes on to the first
    // texel covered at least half, and stops at the first thin one only when it meets nothing
    // else. Stopping at a thin texel would hide the crown behind it.
    vec2 uv = uv0;
    float hit = 1.0;  // 0 when the ray leaves the sphere without meeting a stored surface
    if (u_parallax_steps > 0) {
      hit = 0.0;
      float t_read = 0.0, t_thin = 0.0;  // where the read lies on the ray: the hit, the first thin texel
      bool thin = false;
      float t_front = (u_radius - h0) / rd, t_back = (-u_radius - h0) / rd;
      float dt = (t_back - t_front) / float(u_parallax_steps);
      float slab = 2.0 * abs(dt * rd);  // two steps: no slab can be stepped over
      float prev_gap = -1.0, t_prev = t_front;
      for (int s = 0; s <= u_parallax_steps; ++s) {
        float t = t_front + dt * float(s);
        vec2 uvs = atlas_uv(v_eye_obj + ray * t, k);
        // The stored height of the texel itself, unfiltered: filtering would blend a thin
        // branch's height with the empty back behind it and the ray would stop short of both.
        ivec2 texel = ivec2(uvs * u_atlas_px);
#ifdef SYLVA_DEPTH_COVERAGE
        vec2 depth_coverage = texelFetch(u_depth_coverage, texel, 0).rg;
        float stored = (depth_coverage.r * 2.0 - 1.0) * u_radius;
#else
        float stored = (texelFetch(u_normal_depth, texel, 0).a * 2.0 - 1.0) * u_radius;
#endif
        float gap = (h0 + t * rd) - stored;  // > 0 while the ray is above the stored surface
        // A frame stores the first surface only; behind it may be empty (a twig is not a wall),
        // so a ray more than `slab` below the stored height has passed behind it: keep going.
        if (gap <= 0.0 && gap >= -slab) {
          // Between the last sample above and this one below: where the gap crosses zero.
          float f = s == 0 ? 1.0 : prev_gap / (prev_gap - gap);
          float t_cross = mix(t_prev, t, f);
#ifdef SYLVA_DEPTH_COVERAGE
          if (depth_coverage.g >= 0.5) {
#else
          if (texelFetch(u_color, texel, 0).a >= 0.5) {
#endif
            t_read = t_cross;
            hit = 1.0;
            break;
          }
          if (!thin) t_thin = t_cross;
          thin = true;
        }
        prev_gap = max(gap, 0.0);
        t_prev = t;
      }
      if (hit == 0.0 && thin) {
        t_read = t_thin;
        hit = 1.0;
      }
      if (hit > 0.0) uv = atlas_uv(v_eye_obj + ray * t_read, k);
    }
    vec4 c = textureGrad(u_color, uv, du, dv);                    // premultiplied
    vec3 n = textureGrad(u_normal_depth, uv, du, dv).rgb * 2.0 - c.a;  // normal * coverage
    albedo += (v_weight[k] * hit) * c;
    normal += (v_weight[k] * hit) * n;
  }
  if (albedo.a < 1.0 / 512.0) discard;
  vec3 base = albedo.rgb / albedo.a;
  // The blended normal is a mean over what the texels saw; it is shorter where their normals
  // spread, and diffuse light is linear in it (mean(n . l) = mean(n) . l): keep its length.
  vec3 n_obj = normal / albedo.a;
  vec3 n = length(n_obj) > 1e-6 ? normalize(v_normal_matrix * n_obj) * min(length(n_obj), 1.0) : vec3(0.0);
  vec3 color = base * (u_ambient + u_light_color * max(dot(n, u_light_dir), 0.0));
  o_color = vec4(to_srgb(color.r), to_srgb(color.g), to_srgb(color.b), albedo.a);
}
