// Screen-space fluid, pass 1 (van der Laan, Green & Sainz 2009): the eye distance of the
// nearest fluid sphere in each pixel [L], 0 where there is none.
in vec3 v_center;
in vec3 v_pos;
in vec3 v_color;
in float v_rpx;
uniform mat4 u_proj;
uniform float u_radius;
uniform int u_ortho;
layout(location = 0) out float o_depth;
#ifdef GL_ARB_conservative_depth
layout(depth_greater) out float gl_FragDepth;
#endif
void main() {
    vec3 h;
    vec3 n;
    if (!sphere_hit(v_pos, v_center, u_radius, u_ortho != 0, h, n)) discard;
    gl_FragDepth = window_depth(u_proj, h);
    o_depth = -h.z;
}
