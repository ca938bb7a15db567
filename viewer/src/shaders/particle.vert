#version 330 core
// One instanced 4-vertex strip per particle: a quad in the plane of the sphere's nearest
// view depth (z = c.z + r, view space), so that every point of the sphere lies at or
// behind it (the fragment shaders' depth_greater), spanning the sphere's silhouette: in
// perspective its projection's bounding box, else (orthographic) the square about it.
layout(location = 0) in vec3 a_pos;
layout(location = 1) in float a_value;
layout(location = 2) in float a_kind;
uniform mat4 u_view;
uniform mat4 u_proj;
uniform float u_radius;
uniform vec2 u_range;
uniform int u_hidden;
uniform int u_grey_boundary;
uniform int u_ortho;
// Pixels per world unit: at any depth (orthographic), at unit depth (perspective).
uniform float u_px_scale;
uniform sampler2D u_cmap;
out vec3 v_center;
out vec3 v_pos;
out vec3 v_color;
out float v_rpx;
const vec2 CORNERS[4] = vec2[4](vec2(-1.0, -1.0), vec2(1.0, -1.0), vec2(-1.0, 1.0),
                                vec2(1.0, 1.0));

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

void main() {
    int k = int(a_kind + 0.5);
    v_center = vec3(0.0);
    v_pos = vec3(0.0);
    v_color = vec3(0.0);
    v_rpx = 0.0;
    if (k >= 0 && k < 8 && ((u_hidden >> k) & 1) != 0) {
        gl_Position = vec4(2.0, 2.0, 2.0, 1.0); // outside the clip volume
        return;
    }
    vec3 c = (u_view * vec4(a_pos, 1.0)).xyz;
    vec2 q = CORNERS[gl_VertexID & 3];
    float zq = c.z + u_radius; // the sphere's nearest view depth
    vec2 sx;
    vec2 sy;
    vec3 p;
    if (u_ortho != 0) {
        p = c + vec3(q * u_radius, u_radius);
    } else if (zq < 0.0 && slopes(c.x, c.z, u_radius, sx) && slopes(c.y, c.z, u_radius, sy)) {
        // With the disc of radius r about the centre in that plane (the surface's
        // thickness pass draws it; it reaches a little past the silhouette), widened by
        // a twentieth of a pixel so that rounding never loses an edge pixel.
        float m = 0.05 / u_px_scale;
        vec2 lo = min(vec2(sx.x, sy.x), (c.xy - u_radius) / -zq) - m;
        vec2 hi = max(vec2(sx.y, sy.y), (c.xy + u_radius) / -zq) + m;
        vec2 s = vec2(q.x < 0.0 ? lo.x : hi.x, q.y < 0.0 ? lo.y : hi.y);
        p = vec3(s * -zq, zq);
    } else {
        // The eye in or beside the sphere: a square of 1.5 radii in the same plane.
        p = c + vec3(q * u_radius * 1.5, u_radius);
    }
    v_center = c;
    v_pos = p;
    v_rpx = u_radius * u_px_scale / (u_ortho != 0 ? 1.0 : max(-c.z, 1e-6));
    float span = u_range.y - u_range.x;
    float x = span > 0.0 ? (a_value - u_range.x) / span : 0.0;
    if (isnan(x)) x = 0.0;
    float t = clamp(x, 0.0, 1.0);
    v_color = textureLod(u_cmap, vec2((t * 255.0 + 0.5) / 256.0, 0.5), 0.0).rgb;
    if (k == 2 && u_grey_boundary != 0) v_color = vec3(0.55, 0.55, 0.58);
    gl_Position = u_proj * vec4(p, 1.0);
}
