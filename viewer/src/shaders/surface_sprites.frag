// Screen-space fluid, pass 1 (van der Laan, Green & Sainz 2009): the fluid spheres, drawn
// once into two targets of half the view's resolution, without a depth test.
// 0: the eye distance of the nearest fluid sphere in each pixel [L] (MIN blending over a
//    target cleared to NO_FLUID);
// 1: the fluid's thickness along the pixel's ray [L], summed over the spheres it crosses
//    (additive blending). Each sphere adds its chord through the disc of radius r in its
//    sprite's plane, scaled by u_fill = (particle volume) / (sphere volume), so that the
//    sum is the fluid's thickness even though the drawn spheres overlap.
in vec3 v_center;
in vec3 v_pos;
in vec3 v_color;
in float v_rpx;
uniform float u_radius;
uniform int u_ortho;
uniform float u_fill;
layout(location = 0) out float o_depth;
layout(location = 1) out float o_thickness;
// The eye distance of a pixel without fluid (also in `surface.rs` and the blur).
const float NO_FLUID = 1e30;
void main() {
    vec3 p = sprite_point(v_pos, v_center, u_radius, u_ortho != 0);
    vec2 q = p.xy - v_center.xy;
    float r2 = u_radius * u_radius;
    float d2 = dot(q, q);
    vec3 h;
    vec3 n;
    bool hit = sphere_hit(p, v_center, u_radius, u_ortho != 0, h, n);
    if (!hit && d2 >= r2) discard;
    o_depth = hit ? -h.z : NO_FLUID;
    o_thickness = d2 < r2 ? 2.0 * sqrt(r2 - d2) * u_fill : 0.0;
}
