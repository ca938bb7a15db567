in vec3 v_center;
in vec3 v_pos;
in vec3 v_color;
in float v_rpx;
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
    if (!sphere_hit(v_pos, v_center, u_radius, u_ortho != 0, h, n)) discard;
    gl_FragDepth = window_depth(u_proj, h);
    // A sphere a few pixels across cannot show its shading: the lattice's spheres would
    // alias into Moire bands. Below 4 pixels of radius the shading fades to the sphere's
    // mean (diffuse 0.6, no highlight); orthographic views (2D) keep it.
    float lod = u_ortho != 0 ? 1.0 : smoothstep(1.0, 4.0, v_rpx);
    vec3 flat_ = v_color * (0.3 + 0.7 * 0.6);
    if (lod <= 0.0) {
        o_color = vec4(flat_, 1.0);
        return;
    }
    vec3 l = normalize(vec3(-0.4, 0.6, 0.7));
    float diff = max(dot(n, l), 0.0);
    vec3 hv = normalize(l + vec3(0.0, 0.0, 1.0));
    float spec = pow(max(dot(n, hv), 0.0), 48.0);
    vec3 lit = v_color * (0.3 + 0.7 * diff) + vec3(0.3 * spec);
    o_color = vec4(mix(flat_, lit, lod), 1.0);
}
