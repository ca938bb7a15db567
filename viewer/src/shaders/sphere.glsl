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
