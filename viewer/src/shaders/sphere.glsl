// The view's size in pixels (the surface's shading).
uniform vec2 u_view_size;

#ifdef SPRITE_FS
// What particle.vert hands each sprite: its centre (view space), its colour and shading
// level (particle.frag), and on a quad the sprite-plane point of each fragment.
flat in vec3 v_center;
flat in vec4 v_color;
#ifdef SPRITE_QUADS
in vec3 v_pos;
#endif
// A pixel centre's ray (`sprites.rs`): s = gl_FragCoord.xy * u_ray.xz + u_ray.yw is, in
// perspective, the view x and y where the ray crosses z = -1, orthographic its view x, y.
uniform vec4 u_ray;

// The point of the sprite's plane z = c.z + r (view space) that this fragment shows: on a
// quad the interpolated v_pos, on a point the pixel centre's ray through that plane.
vec3 sprite_point(vec3 c, float r, bool ortho) {
#ifdef SPRITE_QUADS
    return v_pos;
#else
    vec2 s = gl_FragCoord.xy * u_ray.xz + u_ray.yw;
    float zq = c.z + r;
    return ortho ? vec3(s, zq) : vec3(s * -zq, zq);
#endif
}
#endif

// Ray-casts the sphere of radius r about c (view space) through the quad point p. Returns
// false on a miss; else the hit point and the unit normal there (Haines et al., "Precision
// improvements for ray/sphere intersection", Ray Tracing Gems 2019: the stable form).
bool sphere_hit(vec3 p, vec3 c, float r, bool ortho, out vec3 hit, out vec3 n) {
    vec3 ro = ortho ? p : vec3(0.0);
    vec3 rd = ortho ? vec3(0.0, 0.0, -1.0) : normalize(p);
    vec3 oc = ro - c;
    float b = dot(rd, oc);
    // r^2 less the squared distance from the centre to the ray, from that distance's
    // vector: b^2 - (|oc|^2 - r^2) loses every digit to cancellation where the eye is
    // hundreds of radii away (|oc|^2 ~ 1e6 r^2 in float), and the normal then grew past
    // unit length (white highlights on NVIDIA's spheres).
    vec3 q = oc - b * rd;
    float disc = r * r - dot(q, q);
    hit = vec3(0.0);
    n = vec3(0.0, 0.0, 1.0);
    if (disc < 0.0) return false;
    float t = -b - sqrt(disc);
    hit = ro + t * rd;
    n = (hit - c) * (1.0 / r);
    return true;
}

// Window depth (0..1) of a view-space point.
float window_depth(mat4 proj, vec3 h) {
    vec4 clip = proj * vec4(h, 1.0);
    return clamp(0.5 * clip.z / clip.w + 0.5, 0.0, 1.0);
}

// A sphere's lighting at its unit normal n: colour by a diffuse light and a highlight,
// blended by the level of detail lod (colour.glsl's shading_lod: 0 shades the sphere as its
// mean, diffuse 0.6 and no highlight; 1 lit).
vec3 lit_sphere(vec3 colour, float lod, vec3 n) {
    vec3 flat_ = colour * (0.3 + 0.7 * 0.6);
    if (lod <= 0.0) return flat_;
    vec3 l = normalize(vec3(-0.4, 0.6, 0.7));
    float diff = max(dot(n, l), 0.0);
    vec3 hv = normalize(l + vec3(0.0, 0.0, 1.0));
    // x^48 by squaring (x^32 x^16): multiplies where pow takes two special-function
    // operations, which bound the sprites' pass (the H100/H200 shade fragments on few SMs).
    float x = clamp(dot(n, hv), 0.0, 1.0);
    float x2 = x * x;
    float x4 = x2 * x2;
    float x8 = x4 * x4;
    float x16 = x8 * x8;
    float spec = x16 * x16 * x16;
    vec3 lit = colour * (0.3 + 0.7 * diff) + vec3(0.3 * spec);
    return mix(flat_, lit, lod);
}
