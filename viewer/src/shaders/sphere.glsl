// The sprites' drawing (`particle.vert`): 1 where they are points, whose fragments take
// the ray from the pixel (the viewport's size, the inverse projection); 0 on quads.
uniform int u_points;
uniform vec2 u_view_size;
uniform mat4 u_inv_proj;

// The point of the sprite's plane z = c.z + r (view space) that this fragment shows: on a
// quad the interpolated vertex point v_pos, on a point the pixel centre's ray through it.
vec3 sprite_point(vec3 v_pos, vec3 c, float r, bool ortho) {
    if (u_points == 0) return v_pos;
    vec2 ndc = gl_FragCoord.xy / u_view_size * 2.0 - 1.0;
    vec4 e = u_inv_proj * vec4(ndc, 0.0, 1.0);
    vec3 q = e.xyz / e.w;
    float zq = c.z + r;
    return ortho ? vec3(q.xy, zq) : q * (zq / q.z);
}

// Ray-casts the sphere of radius r about c (view space) through the quad point p. Returns
// false on a miss; else the hit point and the unit normal there.
bool sphere_hit(vec3 p, vec3 c, float r, bool ortho, out vec3 hit, out vec3 n) {
    vec3 ro = ortho ? p : vec3(0.0);
    vec3 rd = ortho ? vec3(0.0, 0.0, -1.0) : normalize(p);
    vec3 oc = ro - c;
    float b = dot(rd, oc);
    float cc = dot(oc, oc) - r * r;
    float disc = b * b - cc;
    hit = vec3(0.0);
    n = vec3(0.0, 0.0, 1.0);
    if (disc < 0.0) return false;
    float t = -b - sqrt(disc);
    hit = ro + t * rd;
    n = (hit - c) / r;
    return true;
}

// Window depth (0..1) of a view-space point.
float window_depth(mat4 proj, vec3 h) {
    vec4 clip = proj * vec4(h, 1.0);
    return clamp(0.5 * clip.z / clip.w + 0.5, 0.0, 1.0);
}
