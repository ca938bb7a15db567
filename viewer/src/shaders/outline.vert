#version 330 core
// One instanced quad per box edge, u_width pixels wide in the window.
layout(location = 0) in vec3 a_from;
layout(location = 1) in vec3 a_to;
uniform mat4 u_view_proj;
uniform vec2 u_viewport; // pixels
uniform float u_width;   // pixels
const vec2 CORNERS[6] = vec2[6](vec2(0.0, -1.0), vec2(1.0, -1.0), vec2(1.0, 1.0),
                                vec2(0.0, -1.0), vec2(1.0, 1.0), vec2(0.0, 1.0));
void main() {
    vec4 c0 = u_view_proj * vec4(a_from, 1.0);
    vec4 c1 = u_view_proj * vec4(a_to, 1.0);
    if (c0.w <= 0.0 || c1.w <= 0.0) {
        gl_Position = vec4(2.0, 2.0, 2.0, 1.0); // behind the eye: not drawn
        return;
    }
    vec2 s0 = c0.xy / c0.w * u_viewport * 0.5;
    vec2 s1 = c1.xy / c1.w * u_viewport * 0.5;
    vec2 d = s1 - s0;
    d = dot(d, d) > 0.0 ? normalize(d) : vec2(1.0, 0.0);
    vec2 side = vec2(-d.y, d.x);
    vec2 q = CORNERS[gl_VertexID % 6];
    vec4 c = q.x < 0.5 ? c0 : c1;
    // Half a width sideways and past each end, so that edges meet at the corners.
    vec2 off_px = side * q.y * 0.5 * u_width + d * (q.x < 0.5 ? -0.5 : 0.5) * u_width;
    c.xy += off_px / (u_viewport * 0.5) * c.w;
    // A little towards the eye: a wall's edge stays in front of the fluid against it.
    c.z -= 2e-4 * c.w;
    gl_Position = c;
}
