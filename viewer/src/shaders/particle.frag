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
    // The level of detail (particle.vert): 0 shades the sphere as its mean (diffuse 0.6,
    // no highlight), 1 lit.
    float lod = v_color.a;
    vec3 flat_ = v_color.rgb * (0.3 + 0.7 * 0.6);
    if (lod <= 0.0) {
        o_color = vec4(flat_, 1.0);
        return;
    }
    vec3 l = normalize(vec3(-0.4, 0.6, 0.7));
    float diff = max(dot(n, l), 0.0);
    vec3 hv = normalize(l + vec3(0.0, 0.0, 1.0));
    // x^48 by squaring (x^32 x^16): multiplies where pow takes two special-function
    // operations, which bound this pass (the H100/H200 shade fragments on few SMs).
    float x = clamp(dot(n, hv), 0.0, 1.0);
    float x2 = x * x;
    float x4 = x2 * x2;
    float x8 = x4 * x4;
    float x16 = x8 * x8;
    float spec = x16 * x16 * x16;
    vec3 lit = v_color.rgb * (0.3 + 0.7 * diff) + vec3(0.3 * spec);
    o_color = vec4(mix(flat_, lit, lod), 1.0);
}
