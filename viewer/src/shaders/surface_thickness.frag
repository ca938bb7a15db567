// Screen-space fluid, pass 1b: the fluid's thickness along each pixel's ray [L], summed
// over the spheres it crosses (additive blending, no depth test, into a target of half
// the view's resolution: the shading reads it averaged over about a particle spacing).
// Each sphere adds its chord through the disc of radius r in its sprite's plane, scaled by
// u_fill = (particle volume) / (sphere volume), so that the sum is the fluid's thickness
// even though the drawn spheres overlap.
uniform float u_radius;
uniform int u_ortho;
uniform float u_fill;
layout(location = 0) out float o_thickness;
void main() {
    vec3 p = sprite_point(v_center, u_radius, u_ortho != 0);
    vec2 q = p.xy - v_center.xy;
    float s2 = u_radius * u_radius - dot(q, q);
    if (s2 <= 0.0) discard;
    o_thickness = 2.0 * sqrt(s2) * u_fill;
}
