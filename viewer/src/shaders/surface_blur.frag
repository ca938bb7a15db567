#version 330 core
// Screen-space fluid, pass 2: one direction of a separable bilateral filter of the depth
// [L]. The spatial Gaussian spans about u_world_radius in the world (so far fluid is
// smoothed over fewer pixels); the range weight exp(-(dz / u_depth_sigma)^2) keeps a front
// sheet from blending with fluid behind it. Empty pixels (0 from a blur, NO_FLUID from the
// depth pass, where no sphere is) come out 0 and are skipped.
uniform sampler2D u_depth;
uniform ivec2 u_dir;
uniform float u_world_radius;
uniform float u_px_scale;
uniform float u_depth_sigma;
uniform int u_max_px;
layout(location = 0) out float o_depth;
const float NO_FLUID = 1e30; // the depth pass's clear value (`surface.rs`)
bool fluid(float z) {
    return z > 0.0 && z < NO_FLUID;
}
void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    ivec2 last = textureSize(u_depth, 0) - 1;
    float z = texelFetch(u_depth, p, 0).r;
    if (!fluid(z)) {
        o_depth = 0.0;
        return;
    }
    float rpx = clamp(u_world_radius * u_px_scale / z, 1.0, float(u_max_px));
    int n = int(ceil(rpx));
    float inv_s2 = 2.0 / (rpx * rpx); // sigma = rpx / 2
    float inv_r2 = 1.0 / (u_depth_sigma * u_depth_sigma);
    float sum = 0.0;
    float wsum = 0.0;
    for (int i = -n; i <= n; i++) {
        float s = texelFetch(u_depth, clamp(p + u_dir * i, ivec2(0), last), 0).r;
        if (!fluid(s)) continue;
        float dz = s - z;
        float w = exp(-float(i * i) * 0.5 * inv_s2 - dz * dz * inv_r2);
        sum += s * w;
        wsum += w;
    }
    o_depth = sum / wsum;
}
