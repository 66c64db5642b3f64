#version 330 core
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec2 a_texcoord;
layout(location = 3) in vec4 a_color;
layout(location = 4) in float a_size;
layout(location = 5) in mat4 a_model;
layout(location = 9) in mat3 a_normal_matrix;
layout(location = 12) in float a_copies;  // LINES: coincident copies the line stands for (Primitive::copies)

uniform mat4 u_view;
uniform mat4 u_proj;
uniform float u_viewport_height;
uniform float u_default_point_size;
uniform float u_min_point_size;

out vec3 v_world;
out vec3 v_normal;
out vec2 v_texcoord;
out vec4 v_color;
flat out float v_mirrored;  // 1 when the instance matrix mirrors (det < 0): CW is then the front
out float v_copies;

void main() {
  v_mirrored = determinant(mat3(a_model)) < 0.0 ? 1.0 : 0.0;
  vec4 world = a_model * vec4(a_position, 1.0);
  v_world = world.xyz;
  v_normal = a_normal_matrix * a_normal;
  v_texcoord = a_texcoord;
  v_color = a_color;
  v_copies = a_copies;
  gl_Position = u_proj * u_view * world;
  // Points: _SIZE is a diameter in local metres; scale it like the instance does and project
  // it (pixels = size * focal length in pixels / distance).
  if (a_size > 0.0) {
    float scale = pow(abs(determinant(mat3(a_model))), 1.0 / 3.0);
    float pixels = a_size * scale * u_proj[1][1] * 0.5 * u_viewport_height / gl_Position.w;
    gl_PointSize = max(pixels, u_min_point_size);
  } else {
    gl_PointSize = u_default_point_size;
  }
}
