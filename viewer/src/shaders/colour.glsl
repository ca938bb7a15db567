// A sphere's colour and shading level, shared by the sprites' vertex shader (particle.vert)
// and the splat's resolve (splat.frag): the colour map u_cmap over u_range of the value
// (NaN at the range's start), the boundary (kind 2) grey unless u_grey_boundary is 0.
uniform vec2 u_range;
uniform int u_grey_boundary;
uniform sampler2D u_cmap;

vec3 sphere_colour(float value, int k) {
    float span = u_range.y - u_range.x;
    float x = span > 0.0 ? (value - u_range.x) / span : 0.0;
    if (isnan(x)) x = 0.0;
    float t = clamp(x, 0.0, 1.0);
    vec3 c = textureLod(u_cmap, vec2((t * 255.0 + 0.5) / 256.0, 0.5), 0.0).rgb;
    if (k == 2 && u_grey_boundary != 0) c = vec3(0.55, 0.55, 0.58);
    return c;
}

// A sphere a few pixels across cannot show its shading: the lattice's spheres would alias
// into Moire bands. Below 4 pixels of radius (rpx) the shading fades to the sphere's mean
// (lit_sphere in sphere.glsl); orthographic views keep it.
float shading_lod(float rpx, bool ortho) {
    return ortho ? 1.0 : smoothstep(1.0, 4.0, rpx);
}
