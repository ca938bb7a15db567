#version 330 core
// One instanced quad per particle, in the sphere's front tangent plane (view space).
layout(location = 0) in vec3 a_pos;
layout(location = 1) in float a_value;
layout(location = 2) in float a_kind;
uniform mat4 u_view;
uniform mat4 u_proj;
uniform float u_radius;
uniform float u_quad_scale;
uniform vec2 u_range;
uniform int u_hidden;
uniform int u_grey_boundary;
uniform int u_ortho;
// Pixels per world unit: at any depth (orthographic), at unit depth (perspective).
uniform float u_px_scale;
uniform sampler2D u_cmap;
out vec3 v_center;
out vec3 v_pos;
out vec3 v_color;
out float v_rpx;
const vec2 CORNERS[6] = vec2[6](vec2(-1.0, -1.0), vec2(1.0, -1.0), vec2(1.0, 1.0),
                                vec2(-1.0, -1.0), vec2(1.0, 1.0), vec2(-1.0, 1.0));
void main() {
    int k = int(a_kind + 0.5);
    v_center = vec3(0.0);
    v_pos = vec3(0.0);
    v_color = vec3(0.0);
    v_rpx = 0.0;
    if (k >= 0 && k < 8 && ((u_hidden >> k) & 1) != 0) {
        gl_Position = vec4(2.0, 2.0, 2.0, 1.0); // outside the clip volume
        return;
    }
    vec3 c = (u_view * vec4(a_pos, 1.0)).xyz;
    vec2 q = CORNERS[gl_VertexID % 6];
    // Quad in the sphere's front tangent plane, large enough to hold its silhouette.
    vec3 p = c + vec3(q * u_radius * u_quad_scale, u_radius);
    v_center = c;
    v_pos = p;
    v_rpx = u_radius * u_px_scale / (u_ortho != 0 ? 1.0 : max(-c.z, 1e-6));
    float span = u_range.y - u_range.x;
    float x = span > 0.0 ? (a_value - u_range.x) / span : 0.0;
    if (isnan(x)) x = 0.0;
    float t = clamp(x, 0.0, 1.0);
    v_color = textureLod(u_cmap, vec2((t * 255.0 + 0.5) / 256.0, 0.5), 0.0).rgb;
    if (k == 2 && u_grey_boundary != 0) v_color = vec3(0.55, 0.55, 0.58);
    gl_Position = u_proj * vec4(p, 1.0);
}
