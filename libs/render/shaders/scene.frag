#version 330 core

in vec3 v_world;
in vec3 v_normal;
in vec2 v_texcoord;
in vec4 v_color;
flat in float v_mirrored;
in float v_copies;

uniform vec4 u_base_color;
uniform sampler2D u_texture;
uniform float u_alpha_cutoff;
uniform vec3 u_ambient;
uniform vec3 u_light_color;
uniform vec3 u_light_dir;     // unit, toward the light

out vec4 o_color;

float to_srgb(float c) {
  c = clamp(c, 0.0, 1.0);
  return c <= 0.0031308 ? 12.92 * c : 1.055 * pow(c, 1.0 / 2.4) - 0.055;
}

void main() {
  // glTF 2.0, 3.9.2 (double sided): the front face is the counter-clockwise one (clockwise under a
  // mirroring matrix); the back face of a double-sided material is lit with the reversed normal.
  // Nothing is inferred from the eye: a leaf wound against its normal is dark, as in clients.
  bool front = gl_FrontFacing != (v_mirrored > 0.5);
  if (u_cull_in_shader && !front) discard;
  if (u_round_points) {
    vec2 p = gl_PointCoord * 2.0 - 1.0;
    if (dot(p, p) > 1.0) discard;
  }
  vec4 base = u_base_color * v_color;
  if (u_has_texture) base *= texture(u_texture, v_texcoord);
  // What k copies of this line drawn one over the other cover, drawn once (line_merge.h).
  if (u_line_copies) base.a = 1.0 - pow(1.0 - base.a, v_copies);
  if (u_alpha_mode == 1) {
    if (base.a < u_alpha_cutoff) discard;
    base.a = 1.0;
  } else if (u_alpha_mode == 0) {
    base.a = 1.0;
  }
  vec3 color = base.rgb;
  if (u_lit) {
    // Without normals, the flat face normal (glTF: computed from the triangle) from screen-space
    // derivatives: it faces the eye, which is right for every face that is drawn (a front face,
    // or the back face of a double-sided triangle, whose reversed normal faces the eye).
    vec3 n = u_has_normals ? normalize(v_normal) : normalize(cross(dFdx(v_world), dFdy(v_world)));
    // Lines and points have no faces: their normals are used as given.
    if (u_has_normals && u_two_sided && !front) n = -n;
    color = base.rgb * (u_ambient + u_light_color * max(dot(n, u_light_dir), 0.0));
  }
  o_color = vec4(to_srgb(color.r), to_srgb(color.g), to_srgb(color.b), base.a);
}
