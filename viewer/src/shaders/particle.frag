uniform mat4 u_proj;
uniform float u_radius;
uniform int u_ortho;
out vec4 o_color;
#ifdef GL_ARB_conservative_depth
layout(depth_greater) out float gl_FragDepth;
#endif
void main() {
    vec3 h;
    vec3 n;
    vec3 p = sprite_point(v_center, u_radius, u_ortho != 0);
    if (!sphere_hit(p, v_center, u_radius, u_ortho != 0, h, n)) discard;
    gl_FragDepth = window_depth(u_proj, h);
    o_color = vec4(lit_sphere(v_color.rgb, v_color.a, n), 1.0);
}
