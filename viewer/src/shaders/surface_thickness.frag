// Screen-space fluid, pass 2: the fluid's thickness along each pixel's ray [L], summed over
// the spheres it crosses (additive blending). Each sphere adds its chord, scaled by
// u_fill = (particle volume) / (sphere volume), so that the sum is the fluid's thickness
// even though the drawn spheres overlap.
in vec3 v_center;
in vec3 v_pos;
in vec3 v_color;
in float v_rpx;
uniform float u_radius;
uniform float u_fill;
layout(location = 0) out float o_thickness;
void main() {
    vec2 q = v_pos.xy - v_center.xy;
    float r2 = u_radius * u_radius;
    float d2 = dot(q, q);
    if (d2 >= r2) discard;
    o_thickness = 2.0 * sqrt(r2 - d2) * u_fill;
}
