#version 330 core
// One sprite per particle, in the plane of the sphere's nearest view depth (z = c.z + r,
// view space), so that every point of the sphere lies at or behind it (the fragment
// shaders' depth_greater), spanning the sphere's silhouette: in perspective its
// projection's bounding box, else (orthographic) the square about it. Drawn two ways
// (`sprites.rs`), by two programs of this source: one point per particle (GL_POINTS: a square of
// gl_PointSize pixels about the box's centre; the fragment shaders take the ray from
// gl_FragCoord), or an instanced 4-vertex strip (u_points = 0: the box's corners; the
// fragment shaders take the interpolated v_pos), the program built with SPRITE_QUADS.
// With u_split = 1 the points take the
// sprites that fit u_point_max and the strips the rest (the eye in or beside a sphere, or
// a sprite too wide), so that each sprite is drawn once; with u_split = 0 each pass draws
// every sprite (points wider than u_point_max clamped to it).
layout(location = 0) in vec3 a_pos;
layout(location = 1) in float a_value;
layout(location = 2) in float a_kind;
uniform mat4 u_view;
uniform mat4 u_proj;
uniform float u_radius;
uniform int u_hidden;
uniform int u_ortho;
// Pixels per world unit: at any depth (orthographic), at unit depth (perspective).
uniform float u_px_scale;
uniform int u_split;
// The widest point [px], and the clip-space scale of the viewport widened by half of it
// on each side (points whose centre lies off screen still draw; a scissor keeps the view).
uniform float u_point_max;
uniform vec2 u_clip_scale;
// Flat (one value per sprite; a point's vertex is its only one): the fewer a sprite's
// outputs, the faster the pass (the graphics pipeline's attributes per primitive).
flat out vec3 v_center;
// The colour, and in .a the shading's level of detail (particle.frag).
flat out vec4 v_color;
#ifdef SPRITE_QUADS
out vec3 v_pos;
#else
vec3 v_pos;
#endif

// The least and greatest slope x / -z of the two lines from the eye that touch the circle
// of radius r about (x, z), in a plane through the eye and the view's z axis: the
// centre's direction turned by -+asin(r / d), d = |(x, z)|. False where the eye is in the
// circle or a touching line does not point forward.
bool slopes(float x, float z, float r, out vec2 s) {
    s = vec2(0.0);
    float t2 = x * x + z * z - r * r;
    if (t2 <= 0.0) return false;
    float t = sqrt(t2); // the tangent's length: cos = t / d, sin = r / d (both times d)
    vec2 a = vec2(x * t - z * r, x * r + z * t);
    vec2 b = vec2(x * t + z * r, z * t - x * r);
    if (a.y >= 0.0 || b.y >= 0.0) return false;
    float sa = a.x / -a.y;
    float sb = b.x / -b.y;
    s = vec2(min(sa, sb), max(sa, sb));
    return true;
}

void cull() {
    gl_Position = vec4(2.0, 2.0, 2.0, 1.0); // outside the clip volume
    gl_PointSize = 1.0;
}

void main() {
    int k = int(a_kind + 0.5);
    v_center = vec3(0.0);
    v_pos = vec3(0.0);
    v_color = vec4(0.0);
    if (k >= 0 && k < 8 && ((u_hidden >> k) & 1) != 0) {
        cull();
        return;
    }
    vec3 c = (u_view * vec4(a_pos, 1.0)).xyz;
    float zq = c.z + u_radius; // the sphere's nearest view depth
    vec2 sx;
    vec2 sy;
    // The sprite's bounds in its plane: view x and y (orthographic, and the square), or
    // slopes x / -z and y / -z (the box); its wider side in pixels, 0 for the square.
    vec2 lo;
    vec2 hi;
    float px = 0.0;
    bool box = false;
    if (u_ortho != 0) {
        lo = c.xy - u_radius;
        hi = c.xy + u_radius;
        px = 2.0 * u_radius * u_px_scale;
    } else if (zq < 0.0 && slopes(c.x, c.z, u_radius, sx) && slopes(c.y, c.z, u_radius, sy)) {
        // With the disc of radius r about the centre in that plane (the surface's
        // thickness draws it; it reaches a little past the silhouette), widened by a
        // twentieth of a pixel so that rounding never loses an edge pixel.
        float m = 0.05 / u_px_scale;
        lo = min(vec2(sx.x, sy.x), (c.xy - u_radius) / -zq) - m;
        hi = max(vec2(sx.y, sy.y), (c.xy + u_radius) / -zq) + m;
        px = max(hi.x - lo.x, hi.y - lo.y) * u_px_scale;
        box = true;
    } else {
        // The eye in or beside the sphere: a square of 1.5 radii in the same plane.
        lo = c.xy - 1.5 * u_radius;
        hi = c.xy + 1.5 * u_radius;
    }
    // A point covers the pixels whose centres lie in the square of its size about its
    // centre: one pixel more than the sprite, so that the rounding of either never drops
    // an edge pixel.
    float size = px + 1.0;
    bool as_point = px > 0.0 && size <= u_point_max;
    vec3 p;
#ifndef SPRITE_QUADS
    {
        if (px <= 0.0 || (u_split != 0 && !as_point)) {
            cull();
            return;
        }
        gl_PointSize = min(size, u_point_max);
        vec2 mid = 0.5 * (lo + hi);
        p = vec3(box ? mid * -zq : mid, zq);
    }
#else
    {
        if (u_split != 0 && as_point) {
            cull();
            return;
        }
        int i = gl_VertexID & 3;
        vec2 s = vec2((i & 1) == 0 ? lo.x : hi.x, (i & 2) == 0 ? lo.y : hi.y);
        p = vec3(box ? s * -zq : s, zq);
    }
#endif
    v_center = c;
    v_pos = p;
    // The colour and shading level (colour.glsl).
    float rpx = u_radius * u_px_scale / (u_ortho != 0 ? 1.0 : max(-c.z, 1e-6));
    v_color = vec4(sphere_colour(a_value, k), shading_lod(rpx, u_ortho != 0));
    gl_Position = u_proj * vec4(p, 1.0);
    gl_Position.xy *= u_clip_scale;
}
