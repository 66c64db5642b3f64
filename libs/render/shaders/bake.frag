#version 330 core

#if HAS_NORMALS
in vec3 v_normal;
#else
in vec3 v_world;
#endif
#if MERGED_LINES
in vec3 v_normal1;
in vec3 v_normal2;
flat in float v_copies;
#endif
#if HAS_TEXTURE
in vec2 v_texcoord;
#endif
#if HAS_COLORS
in vec4 v_color;
#endif
flat in vec3 v_dir;
in float v_depth;

uniform vec4 u_base_color;
uniform sampler2D u_texture;
uniform int u_alpha_mode;  // 0 opaque, 1 mask, 2 blend
uniform float u_alpha_cutoff;
uniform bool u_two_sided;     // glTF doubleSided triangles: a back face uses the reversed normal
uniform bool u_mirrored;      // the instance matrix mirrors: clockwise is the front
uniform float u_alpha_scale;  // lines thinner than a texel: their coverage spread over one texel

#if OPAQUE_LAYER
// The opaque layer (msaa 1, opaque and masked primitives): every map's 8-bit value in one
// unsigned 16-bit RGBA texel (BakeLayout::kLayered in the renderer).
layout(location = 3) out uvec4 o_packed;
#else
layout(location = 0) out vec4 o_color;
layout(location = 1) out vec4 o_normal;
layout(location = 2) out vec4 o_depth;
#endif

float to_srgb(float c) {
  c = clamp(c, 0.0, 1.0);
  return c <= 0.0031308 ? 12.92 * c : 1.055 * pow(c, 1.0 / 2.4) - 0.055;
}

void main() {
  vec4 base = u_base_color;
#if HAS_COLORS
  base *= v_color;
#endif
#if HAS_TEXTURE
  base *= texture(u_texture, v_texcoord);
#endif
  if (u_alpha_mode == 1) {
    if (base.a < u_alpha_cutoff) discard;
    base.a = 1.0;
  } else if (u_alpha_mode == 0) {
    base.a = 1.0;
  }
  base.a *= u_alpha_scale;
  // The scene renderer's rules (gl_renderer.cpp, glTF 2.0 3.9.2): the front face is the
  // counter-clockwise one (clockwise under a mirroring matrix), a double-sided back face is lit
  // with the reversed normal; without normals, the face normal, which faces the view.
  bool front = gl_FrontFacing != u_mirrored;
#if HAS_NORMALS
  vec3 n = normalize(v_normal);
  if (u_two_sided && !front) n = -n;
#else
  vec3 n = normalize(cross(dFdx(v_world), dFdy(v_world)));
#endif
  // Lines stand for twigs, which the full detail draws as lit cylinders: bake their normals
  // turned toward the view (the renderer draws LINES unlit, as three.js does; an impostor is lit).
#if IS_LINES
  if (dot(n, v_dir) < 0.0) n = -n;
#elif MERGED_LINES
  int copies = int(v_copies + 0.5);
  if (copies <= 1) {
    if (dot(n, v_dir) < 0.0) n = -n;
  } else {
    // k coincident lines of alpha a drawn as one (line_merge.h): the copy drawn last weighs a,
    // the one before a (1 - a), ...; together they cover 1 - (1 - a)^k, and their normals (each
    // turned toward the view) average with the same weights, as k overs would composite them.
    float a = base.a, w = a, cover = 0.0;
    vec3 sum = vec3(0.0);
    for (int j = copies - 1; j >= 0; --j) {
      vec3 nj = n;
#if HAS_NORMALS
      nj = normalize(j == 0 ? v_normal : j == 1 ? v_normal1 : v_normal2);
#endif
      if (dot(nj, v_dir) < 0.0) nj = -nj;
      sum += w * nj;
      cover += w;
      w *= 1.0 - a;
    }
    if (cover > 0.0) n = sum / cover;
    base.a = cover;
  }
#endif
#if OPAQUE_LAYER
  // Covered (alpha 1): colour, normal and depth as the maps store them, rounded to 8 bits, and
  // 0xFF in the top byte of alpha (covered; the layer is cleared to 0).
  uvec3 c8 = uvec3(vec3(to_srgb(base.r), to_srgb(base.g), to_srgb(base.b)) * 255.0 + 0.5);
  uvec3 n8 = uvec3(clamp(n * 0.5 + 0.5, 0.0, 1.0) * 255.0 + 0.5);
  uint d8 = uint(clamp(v_depth * 0.5 + 0.5, 0.0, 1.0) * 255.0 + 0.5);
  o_packed = uvec4(c8.r | (c8.g << 8), c8.b | (n8.x << 8), n8.y | (n8.z << 8), d8 | 0xFF00u);
#else
  o_color = vec4(to_srgb(base.r), to_srgb(base.g), to_srgb(base.b), base.a);
  o_normal = vec4(n * 0.5 + 0.5, base.a);
  o_depth = vec4(clamp(v_depth * 0.5 + 0.5, 0.0, 1.0), 0.0, 0.0, base.a);
#endif
}
