#version 330 core
// sylva's reference vertex shader for (hemi-)octahedral impostors: frame selection.
// docs/stages/impostor.md explains every uniform and formula; impostor.json carries the values.
// Public domain (CC0): copy it into your engine. libs/render draws impostors with this file.
//
// One impostor instance is one quad: 4 vertices with a_corner in {-1, 1}^2 (two triangles),
// a_model its object -> world matrix (rotation, translation, uniform scale).

layout(location = 0) in vec2 a_corner;
layout(location = 1) in mat4 a_model;  // locations 1-4, one per instance

uniform mat4 u_view;
uniform mat4 u_proj;
uniform vec3 u_eye;           // camera position, world space
uniform int u_frames;         // atlas.frames_per_side, N
uniform bool u_hemi;          // hemi_octahedral
uniform vec3 u_center;        // sphere.center, object space
uniform float u_radius;       // sphere.radius_m, R

out vec3 v_obj;               // object-space point of the quad
flat out vec3 v_eye_obj;      // camera position, object space
flat out vec3 v_dir[3];       // the three frames' directions (centre toward viewer) ...
flat out vec3 v_right[3];     // ... and image bases
flat out vec3 v_up[3];
flat out vec2 v_cell[3];      // the three frames' (column, row)
flat out vec3 v_weight;       // their barycentric weights
flat out mat3 v_normal_matrix;  // object -> world for normals

// Hemi-octahedral / octahedral maps (impostor.json frame_direction_formula).
vec2 encode_direction(vec3 v) {
  if (u_hemi && v.y < 0.0) {
    v.y = 0.0;
    v = length(v.xz) > 1e-9 ? normalize(v) : vec3(0.0, 0.0, 1.0);
  }
  vec3 q = v / (abs(v.x) + abs(v.y) + abs(v.z));
  if (u_hemi) return vec2(q.x + q.z, q.x - q.z);
  if (q.y >= 0.0) return q.xz;
  return vec2((1.0 - abs(q.z)) * (q.x >= 0.0 ? 1.0 : -1.0), (1.0 - abs(q.x)) * (q.z >= 0.0 ? 1.0 : -1.0));
}

vec3 decode_direction(vec2 p) {
  p = clamp(p, -1.0, 1.0);
  vec3 q;
  if (u_hemi) {
    float x = 0.5 * (p.x + p.y), z = 0.5 * (p.x - p.y);
    q = vec3(x, 1.0 - abs(x) - abs(z), z);
  } else {
    q = vec3(p.x, 1.0 - abs(p.x) - abs(p.y), p.y);
    if (q.y < 0.0) q.xz = vec2((1.0 - abs(p.y)) * (p.x >= 0.0 ? 1.0 : -1.0), (1.0 - abs(p.x)) * (p.y >= 0.0 ? 1.0 : -1.0));
  }
  return normalize(q);
}

void frame_basis(vec3 d, out vec3 right, out vec3 up) {
  right = abs(d.y) > 1.0 - 1e-6 ? vec3(1.0, 0.0, 0.0) : normalize(cross(vec3(0.0, 1.0, 0.0), d));
  up = normalize(cross(d, right));
}

void main() {
  vec3 eye = (inverse(a_model) * vec4(u_eye, 1.0)).xyz;
  vec3 to_eye = eye - u_center;
  float dist = max(length(to_eye), 1e-6);
  vec3 view = to_eye / dist;

  // Frame selection: the grid cell of the view direction and its triangle (barycentric weights).
  float m = float(u_frames - 1);
  vec2 g = (encode_direction(view) * 0.5 + 0.5) * m;
  vec2 c = clamp(floor(g), vec2(0.0), vec2(m - 1.0));
  vec2 f = clamp(g - c, 0.0, 1.0);
  if (f.x + f.y <= 1.0) {
    v_cell[0] = c;
    v_weight = vec3(1.0 - f.x - f.y, f.x, f.y);
  } else {
    v_cell[0] = c + vec2(1.0, 1.0);
    v_weight = vec3(f.x + f.y - 1.0, 1.0 - f.y, 1.0 - f.x);
  }
  v_cell[1] = c + vec2(1.0, 0.0);
  v_cell[2] = c + vec2(0.0, 1.0);
  for (int k = 0; k < 3; ++k) {
    v_dir[k] = decode_direction(v_cell[k] / m * 2.0 - 1.0);
    frame_basis(v_dir[k], v_right[k], v_up[k]);
  }

  // The quad faces the eye and covers the sphere's silhouette, R d / sqrt(d^2 - R^2) on the plane
  // through the centre.
  vec3 right, up;
  frame_basis(view, right, up);
  float half_size = u_radius * dist / sqrt(max(dist * dist - u_radius * u_radius, 1e-4 * u_radius * u_radius));
  v_obj = u_center + half_size * 1.001 * (a_corner.x * right + a_corner.y * up);
  v_eye_obj = eye;
  v_normal_matrix = transpose(inverse(mat3(a_model)));
  gl_Position = u_proj * u_view * a_model * vec4(v_obj, 1.0);
}
