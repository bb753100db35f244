#pragma once
// Private: GLSL 3.30 core sources for the preview renderer. Lighting is done in eye space, so
// the key light always comes from the viewer's upper left whatever the camera.
namespace invfem::renders::detail {

// Full-screen triangle from gl_VertexID (no vertex buffer), vertical gradient.
inline constexpr const char* kBackgroundVertex = R"(#version 330 core
out float v_height;
void main() {
  vec2 p = vec2(gl_VertexID == 1 ? 3.0 : -1.0, gl_VertexID == 2 ? 3.0 : -1.0);
  v_height = 0.5 * (p.y + 1.0);
  gl_Position = vec4(p, 0.0, 1.0);
}
)";
inline constexpr const char* kBackgroundFragment = R"(#version 330 core
in float v_height;
uniform vec3 u_top;
uniform vec3 u_bottom;
out vec4 o_color;
void main() { o_color = vec4(mix(u_bottom, u_top, smoothstep(0.0, 1.0, v_height)), 1.0); }
)";

// Interleaved vertex: position (shifted by the scene origin), normal (zero = degenerate), colour.
inline constexpr const char* kMeshVertex = R"(#version 330 core
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec3 a_color;
uniform mat4 u_view;
uniform mat4 u_projection;
out vec3 v_eye_position;
out vec3 v_normal;
out vec3 v_color;
void main() {
  vec4 eye = u_view * vec4(a_position, 1.0);
  v_eye_position = eye.xyz;
  v_normal = mat3(u_view) * a_normal;  // the view is rigid, so no inverse transpose
  v_color = a_color;
  gl_Position = u_projection * eye;
}
)";
inline constexpr const char* kMeshFragment = R"(#version 330 core
in vec3 v_eye_position;
in vec3 v_normal;
in vec3 v_color;
uniform vec3 u_back_color;
uniform float u_back_mix;   // 0: back side in the front colour; 1: back_color; 0.5: half-way
uniform vec3 u_key_direction;   // eye space, unit, towards the light
uniform vec3 u_fill_direction;
out vec4 o_color;
void main() {
  vec3 to_eye = normalize(-v_eye_position);
  float len = length(v_normal);
  // Degenerate face (zero normal): shade it as if it faced the camera rather than emit NaN.
  vec3 n = len > 1e-6 ? v_normal / len : to_eye;
  vec3 base = v_color;
  if (!gl_FrontFacing) {
    base = mix(v_color, u_back_color, u_back_mix);
    if (len > 1e-6) n = -n;
  }
  float key = max(dot(n, u_key_direction), 0.0);
  float fill = max(dot(n, u_fill_direction), 0.0);
  vec3 h = normalize(u_key_direction + to_eye);
  float spec = key > 0.0 ? pow(max(dot(n, h), 0.0), 48.0) : 0.0;
  vec3 c = base * (0.26 + 0.62 * key + 0.22 * fill) + vec3(0.10 * spec);
  o_color = vec4(min(c, vec3(1.0)), 1.0);
}
)";

// Ground quad at world y = 0; grid lines every u_spacing world units, antialiased with fwidth
// and faded out where cells shrink to a few pixels; alpha fades to 0 at u_radius from centre.
inline constexpr const char* kGroundVertex = R"(#version 330 core
layout(location = 0) in vec3 a_position;
uniform mat4 u_view;
uniform mat4 u_projection;
out vec3 v_position;
void main() {
  v_position = a_position;
  gl_Position = u_projection * (u_view * vec4(a_position, 1.0));
}
)";
inline constexpr const char* kGroundFragment = R"(#version 330 core
in vec3 v_position;
uniform vec2 u_origin_xz;   // added back to get world x, z for the grid
uniform vec2 u_center_xz;   // fade centre, shifted coordinates
uniform float u_radius;
uniform float u_spacing;
uniform vec3 u_ground_color;
uniform vec3 u_line_color;
out vec4 o_color;
void main() {
  vec2 coord = (v_position.xz + u_origin_xz) / u_spacing;
  vec2 fw = max(fwidth(coord), vec2(1e-6));
  vec2 g = abs(fract(coord - 0.5) - 0.5) / fw;
  float line = 1.0 - min(min(g.x, g.y), 1.0);
  line *= 1.0 - smoothstep(0.15, 0.5, max(fw.x, fw.y));
  vec3 c = mix(u_ground_color, u_line_color, 0.6 * line);
  float d = length(v_position.xz - u_center_xz);
  float alpha = 1.0 - smoothstep(0.35 * u_radius, u_radius, d);
  o_color = vec4(c, alpha);
}
)";

}  // namespace invfem::renders::detail
