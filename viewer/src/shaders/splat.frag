// The visibility splat's resolve (`splat.rs`): at each pixel the nearest sphere that the
// source's splat found (the splat's buffer through two buffer textures: u_px, texel p =
// pixel p's world centre and value; u_pk, texel u_kinds_at + p = its kind, 255 where none;
// pixel (X, Y) is p = Y u_width + X), ray-cast and lit as particle.frag lights a sprite
// (perspective only). It is the view's first pass and covers all of it, so the view is not
// cleared: a pixel with no sphere gets the background and the far depth that a clear gives.
uniform mat4 u_view;
uniform mat4 u_proj;
uniform float u_radius;
uniform float u_px_scale;
uniform vec4 u_ray;
uniform samplerBuffer u_px;
uniform usamplerBuffer u_pk;
uniform int u_width;
uniform int u_kinds_at;
uniform vec3 u_background;
out vec4 o_color;
void background() {
    gl_FragDepth = 1.0;
    o_color = vec4(u_background, 1.0);
}
void main() {
    ivec2 q = ivec2(gl_FragCoord.xy);
    int p = q.y * u_width + q.x;
    uint k = texelFetch(u_pk, u_kinds_at + p).r;
    if (k == 255u) {
        background();
        return;
    }
    vec4 d = texelFetch(u_px, p);
    vec3 c = (u_view * vec4(d.xyz, 1.0)).xyz;
    // The pixel's point in the sprite's plane (sphere.glsl's sprite_point of a point).
    vec2 s = gl_FragCoord.xy * u_ray.xz + u_ray.yw;
    float zq = c.z + u_radius;
    vec3 h;
    vec3 n;
    if (!sphere_hit(vec3(s * -zq, zq), c, u_radius, false, h, n)) {
        background();
        return;
    }
    gl_FragDepth = window_depth(u_proj, h);
    float rpx = u_radius * u_px_scale / max(-c.z, 1e-6);
    o_color = vec4(lit_sphere(sphere_colour(d.w, int(k)), shading_lod(rpx, false), n), 1.0);
}
