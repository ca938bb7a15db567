// Screen-space fluid, pass 3: shade the smoothed depth, at the view's resolution: the
// distance (smoothed at u_depth_div times fewer pixels along x and y) taken up bilinearly
// over the texels of the nearest sheet (`eye_distance`). Normals from the view-space
// positions of the neighbouring pixels (the smaller difference on each axis, so that a
// silhouette does not bend them); Fresnel reflection of a sky (Schlick's approximation,
// water F0 = 0.02); Beer-Lambert absorption over the thickness. Blending is
// dual-source: the framebuffer's colour behind is multiplied by o_trans (the light that
// crosses the water) and o_color is added.
uniform sampler2D u_depth;
uniform sampler2D u_thickness;
uniform vec2 u_depth_div;  // view pixels per u_depth texel, x and y (u_view_size: sphere.glsl)
uniform mat4 u_proj;
uniform mat3 u_to_world;
uniform vec2 u_tan_half; // tan of half the field of view, x and y
uniform vec3 u_light;    // view space, unit
uniform vec3 u_absorb;   // [1/L] per channel
uniform vec3 u_water;    // colour scattered by deep water
uniform float u_spacing_px; // a particle spacing in thickness texels at unit distance
uniform float u_edge_dz;    // [L] a neighbour this much nearer or farther is another sheet
layout(location = 0, index = 0) out vec4 o_color;
layout(location = 0, index = 1) out vec4 o_trans;

vec3 view_pos(ivec2 p, float z) {
    vec2 ndc = (vec2(p) + 0.5) / u_view_size * 2.0 - 1.0;
    return vec3(ndc * u_tan_half * z, -z);
}

// The smoothed eye distance at the centre of view pixel p; 0 without fluid. Bilinear over
// the four nearest texels, of those that hold fluid only the ones nearer than the nearest
// plus u_edge_dz per view pixel between texels (a sheet is not averaged with fluid behind
// it, a surface seen at a grazing angle is); the pixel holds fluid where the texels with
// fluid weigh at least half, so that silhouettes run between texel centres.
float eye_distance(ivec2 p) {
    ivec2 last = textureSize(u_depth, 0) - 1;
    vec2 t = (vec2(p) + 0.5) / u_depth_div - 0.5;
    vec2 t0 = floor(t);
    vec2 f = t - t0;
    ivec2 i0 = ivec2(t0);
    float z[4];
    float w[4];
    float near = 1e30;
    float covered = 0.0;
    for (int k = 0; k < 4; k++) {
        ivec2 d = ivec2(k & 1, k >> 1);
        z[k] = texelFetch(u_depth, clamp(i0 + d, ivec2(0), last), 0).r;
        w[k] = (d.x == 1 ? f.x : 1.0 - f.x) * (d.y == 1 ? f.y : 1.0 - f.y);
        if (z[k] > 0.0) {
            near = min(near, z[k]);
            covered += w[k];
        }
    }
    if (covered < 0.5) return 0.0;
    float sheet = near + u_edge_dz * max(u_depth_div.x, u_depth_div.y);
    float sum = 0.0;
    float ws = 0.0;
    for (int k = 0; k < 4; k++) {
        if (z[k] > 0.0 && z[k] <= sheet) {
            sum += w[k] * z[k];
            ws += w[k];
        }
    }
    return sum / ws;
}

// The difference along one axis: forward or backward, whichever is shorter in depth
// (a missing neighbour, or one on another sheet, never counts; `edge` is set where one is).
vec3 tangent(ivec2 p, vec3 c, ivec2 d, inout bool edge) {
    ivec2 g_last = ivec2(u_view_size) - 1;
    ivec2 pa = clamp(p + d, ivec2(0), g_last);
    ivec2 pb = clamp(p - d, ivec2(0), g_last);
    float z = -c.z;
    float za = eye_distance(pa);
    float zb = eye_distance(pb);
    if (abs(za - z) > u_edge_dz) za = 0.0;
    if (abs(zb - z) > u_edge_dz) zb = 0.0;
    vec3 fa = za > 0.0 ? view_pos(pa, za) - c : vec3(0.0);
    vec3 fb = zb > 0.0 ? c - view_pos(pb, zb) : vec3(0.0);
    edge = edge || za <= 0.0 || zb <= 0.0;
    if (za <= 0.0) return fb;
    if (zb <= 0.0) return fa;
    return abs(fa.z) < abs(fb.z) ? fa : fb;
}

vec3 sky(vec3 d) {
    vec3 horizon = vec3(0.78, 0.82, 0.86);
    vec3 zenith = vec3(0.30, 0.50, 0.80);
    vec3 ground = vec3(0.16, 0.16, 0.18);
    return d.y >= 0.0 ? mix(horizon, zenith, sqrt(d.y)) : mix(horizon, ground, sqrt(-d.y));
}

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    float z = eye_distance(p);
    if (z <= 0.0) discard;
    vec3 c = view_pos(p, z);
    bool edge = false;
    vec3 tx = tangent(p, c, ivec2(1, 0), edge);
    vec3 ty = tangent(p, c, ivec2(0, 1), edge);
    vec3 n = cross(tx, ty);
    n = dot(n, n) > 0.0 ? normalize(n) : vec3(0.0, 0.0, 1.0);
    vec3 v = normalize(-c);
    if (dot(n, v) < 0.0) n = -n;
    // On the silhouette the normal is a guess: lean it towards the eye, so that the
    // outline does not flash with grazing reflections.
    if (edge) n = normalize(n + v);
    float cos_v = clamp(dot(n, v), 0.0, 1.0);
    float fresnel = 0.02 + 0.98 * pow(1.0 - cos_v, 5.0);
    vec3 reflected = sky(normalize(u_to_world * reflect(-v, n)));
    float diffuse = 0.3 + 0.7 * max(dot(n, u_light), 0.0);
    // No highlight on the silhouette, where the normal is a guess.
    float spec = edge ? 0.0 : pow(max(dot(n, normalize(u_light + v)), 0.0), 60.0);
    // The thickness (at a lower resolution) averaged over about one particle spacing (its
    // mipmaps).
    vec2 uv = (vec2(p) + 0.5) / u_view_size;
    float lod = log2(max(u_spacing_px / z, 1.0));
    vec3 trans = exp(-u_absorb * textureLod(u_thickness, uv, lod).r);
    vec3 body = u_water * diffuse * (vec3(1.0) - trans);
    o_color = vec4((1.0 - fresnel) * body + fresnel * reflected + vec3(0.4 * spec), 1.0);
    o_trans = vec4((1.0 - fresnel) * trans, 1.0);
    gl_FragDepth = window_depth(u_proj, c);
}
