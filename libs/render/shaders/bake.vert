#version 330 core

layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec2 a_texcoord;
layout(location = 3) in vec4 a_color;
#if MERGED_LINES
// Merged lines (line_merge.h): the second and third copies' normals and the number of copies.
layout(location = 4) in vec3 a_normal1;
layout(location = 5) in vec3 a_normal2;
layout(location = 6) in float a_copies;
#endif

uniform mat4 u_model;
uniform mat3 u_normal_matrix;
// Per view of the row (gl_InstanceID): centre, right / half width, up / half height,
// dir / depth radius, and the view's rectangle in NDC (centre x, y, half width, half height).
uniform vec4 u_views[5 * 64];

#if HAS_NORMALS
out vec3 v_normal;
#else
out vec3 v_world;
#endif
#if MERGED_LINES
out vec3 v_normal1;
out vec3 v_normal2;
flat out float v_copies;
#endif
#if HAS_TEXTURE
out vec2 v_texcoord;
#endif
#if HAS_COLORS
out vec4 v_color;
#endif
flat out vec3 v_dir;
out float v_depth;

void main() {
  int b = gl_InstanceID * 5;
  vec3 c = u_views[b].xyz;
  vec3 r = u_views[b + 1].xyz;
  vec3 u = u_views[b + 2].xyz;
  vec3 d = u_views[b + 3].xyz;
  vec4 rect = u_views[b + 4];
  vec4 world = u_model * vec4(a_position, 1.0);
  vec3 a = world.xyz - c;
  float s = dot(a, r), t = dot(a, u), z = dot(a, d);
  // Every view frames the whole source (layouts fit the bounding sphere), so nothing reaches a
  // neighbouring view's rectangle and no clipping is needed.
  gl_Position = vec4(rect.x + s * rect.z, rect.y + t * rect.w, -z, 1.0);
#if HAS_NORMALS
  v_normal = u_normal_matrix * a_normal;
#else
  v_world = world.xyz;
#endif
#if MERGED_LINES
  v_normal1 = u_normal_matrix * a_normal1;
  v_normal2 = u_normal_matrix * a_normal2;
  v_copies = a_copies;
#endif
#if HAS_TEXTURE
  v_texcoord = a_texcoord;
#endif
#if HAS_COLORS
  v_color = a_color;
#endif
  v_dir = normalize(d);
  v_depth = z;
}
