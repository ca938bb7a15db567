// Screen-space fluid, pass 1a (van der Laan, Green & Sainz 2009): the eye distance of the
// nearest fluid sphere in each pixel [L], into a target cleared to NO_FLUID, through a real
// depth buffer (test LESS, written): the sprites are drawn front to back and declare their
// depth behind the sprite's plane (depth_greater), so that the spheres hidden behind nearer
// ones are rejected before this shader runs.
uniform mat4 u_proj;
uniform float u_radius;
uniform int u_ortho;
layout(location = 0) out float o_depth;
#ifdef GL_ARB_conservative_depth
layout(depth_greater) out float gl_FragDepth;
#endif
void main() {
    vec3 p = sprite_point(v_center, u_radius, u_ortho != 0);
    vec3 h;
    vec3 n;
    if (!sphere_hit(p, v_center, u_radius, u_ortho != 0, h, n)) discard;
    o_depth = -h.z;
    gl_FragDepth = window_depth(u_proj, h);
}
