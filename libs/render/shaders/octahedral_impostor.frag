#version 330 core
// sylva's reference fragment shader for (hemi-)octahedral impostors: per frame, intersect the
// view ray with the frame's plane, step along the ray to the depth the frame stored (parallax),
// sample; blend the three frames by their weights; light like sylva's renderer.
// docs/stages/impostor.md explains every uniform and formula. Public domain (CC0).

in vec3 v_obj;
flat in vec3 v_eye_obj;
flat in vec3 v_dir[3];
flat in vec3 v_right[3];
flat in vec3 v_up[3];
flat in vec2 v_cell[3];
flat in vec3 v_weight;
flat in mat3 v_normal_matrix;

uniform sampler2D u_color;         // atlas.color: sRGB texture (GL_SRGB8_ALPHA8), alpha = coverage
uniform sampler2D u_normal_depth;  // atlas.normal_depth: linear RGBA8, rgb = normal, a = depth
uniform int u_frames;              // N
uniform vec3 u_center;             // sphere.center
uniform float u_radius;            // sphere.radius_m, R
uniform float u_half_extent;       // frame_half_extent_m, W
uniform float u_padding;           // atlas.padding_px / atlas.frame_px
uniform int u_parallax_steps;      // 2
uniform vec3 u_ambient;            // linear RGB (sylva: 0.35)
uniform vec3 u_light_color;        // linear RGB (sylva: 0.75)
uniform vec3 u_light_dir;          // unit, world space, toward the light

out vec4 o_color;

// Frame uv (0,0 top-left .. 1,1) of an object-space point, then atlas uv, kept inside the frame's
// padding so no mip level up to atlas.mip_levels reads a neighbouring frame.
vec2 atlas_uv(vec3 x, int k) {
  vec3 a = x - u_center;
  vec2 fuv = vec2(0.5 + dot(a, v_right[k]) / (2.0 * u_half_extent), 0.5 - dot(a, v_up[k]) / (2.0 * u_half_extent));
  fuv = clamp(fuv, vec2(u_padding), vec2(1.0 - u_padding));
  return (v_cell[k] + fuv) / float(u_frames);
}

float to_srgb(float c) {
  c = clamp(c, 0.0, 1.0);
  return c <= 0.0031308 ? 12.92 * c : 1.055 * pow(c, 1.0 / 2.4) - 0.055;
}

void main() {
  vec3 ray = normalize(v_obj - v_eye_obj);
  vec4 albedo = vec4(0.0);  // premultiplied, linear
  vec3 normal = vec3(0.0);
  for (int k = 0; k < 3; ++k) {
    float rd = min(dot(ray, v_dir[k]), -1e-4);  // the ray runs against the frame's direction
    vec3 x = v_eye_obj + ray * (dot(u_center - v_eye_obj, v_dir[k]) / rd);  // on the frame plane
    vec2 uv0 = atlas_uv(x, k);
    vec2 du = dFdx(uv0), dv = dFdy(uv0);  // mip level from the plane, not from the parallax jumps
    vec2 uv = uv0;
    for (int s = 0; s < u_parallax_steps; ++s) {
      float h = (textureGrad(u_normal_depth, uv, du, dv).a * 2.0 - 1.0) * u_radius;
      uv = atlas_uv(x + ray * (h / rd), k);  // the ray's point h above the plane
    }
    vec4 c = textureGrad(u_color, uv, du, dv);
    vec3 n = textureGrad(u_normal_depth, uv, du, dv).rgb * 2.0 - 1.0;
    albedo += v_weight[k] * vec4(c.rgb * c.a, c.a);
    normal += (v_weight[k] * c.a) * n;
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
