// SPDX-License-Identifier: MIT
/**
 * @file xs_env.glsl
 * @brief The environment seen by escaping rays: the equirectangular map of XS_BIND_ENV_MAP
 *        (lookup, pdf, importance sampling by its marginal/conditional cdf) and the sun disk.
 *
 * Map convention, pdf and layout: plugin/src/scene/sc_env.h and XS_ENV_* in xrsc_shared.h.
 * The map's radiance is piecewise constant per texel (nearest lookup), so sampling a texel
 * by its cdf and a point uniformly inside it has exactly the pdf that xs_env_pdf returns.
 * Requires xs_bindings.glsl and xs_sampling.glsl.
 */
#ifndef XS_ENV_GLSL
#define XS_ENV_GLSL

/** Texel index of unit direction d, and sin(theta) of d in *s. */
uint xs_env_texel(vec3 d, out float s)
{
    float u = fract(0.5 + (atan(d.x, -d.z) - frame.env_rotation) / XS_TWO_PI);
    float cy = clamp(d.y, -1.0, 1.0);
    float v = acos(cy) / XS_PI;
    s = sqrt(max(0.0, 1.0 - cy * cy));
    uint x = min(uint(u * float(frame.env_width)), frame.env_width - 1u);
    uint y = min(uint(v * float(frame.env_height)), frame.env_height - 1u);
    return y * frame.env_width + x;
}

/** Radiance of the map towards unit d (frame.env_width > 0). */
vec3 xs_env_radiance(vec3 d)
{
    float s;
    uint i = xs_env_texel(d, s);
    return vec3(env_map[4u * i], env_map[4u * i + 1u], env_map[4u * i + 2u]);
}

/** Solid-angle pdf of xs_env_sample returning unit d. */
float xs_env_pdf(vec3 d)
{
    float s;
    uint i = xs_env_texel(d, s);
    return s > 0.0 ? env_map[4u * i + 3u] / s : 0.0;
}

/** First index in [0, count) of env_map[base + i] > u (the cdf is inclusive, last = 1). */
uint xs_env_search(uint base, uint count, float u)
{
    uint lo = 0u, hi = count - 1u;
    while (lo < hi) {
        uint mid = (lo + hi) >> 1u;
        if (env_map[base + mid] > u)
            hi = mid;
        else
            lo = mid + 1u;
    }
    return lo;
}

/** Samples a direction by the map's luminance x sin(theta); returns its radiance, the
 *  direction in wi and the solid-angle pdf in pdf (0: no sample). */
vec3 xs_env_sample(vec2 u, out vec3 wi, out float pdf)
{
    uint w = frame.env_width, h = frame.env_height, n = w * h;
    uint mbase = XS_ENV_MARGINAL(n);
    uint y = xs_env_search(mbase, h, u.x);
    float c0 = y > 0u ? env_map[mbase + y - 1u] : 0.0;
    float fy = clamp((u.x - c0) / max(env_map[mbase + y] - c0, 1e-30), 0.0, 0.99999);
    uint cbase = XS_ENV_CONDITIONAL(n, h) + y * w;
    uint x = xs_env_search(cbase, w, u.y);
    float d0 = x > 0u ? env_map[cbase + x - 1u] : 0.0;
    float fx = clamp((u.y - d0) / max(env_map[cbase + x] - d0, 1e-30), 0.0, 0.99999);
    /* reuse the remainders of u for the position inside the texel */
    float phi = ((float(x) + fx) / float(w) - 0.5) * XS_TWO_PI + frame.env_rotation;
    float theta = (float(y) + fy) / float(h) * XS_PI;
    float s = sin(theta);
    wi = vec3(s * sin(phi), cos(theta), -s * cos(phi));
    uint i = y * w + x;
    pdf = s > 0.0 ? env_map[4u * i + 3u] / s : 0.0;
    return vec3(env_map[4u * i], env_map[4u * i + 1u], env_map[4u * i + 2u]);
}

/** Solid angle of the sun disk (frame.sun_cos_max > 0). */
float xs_sun_solid_angle() { return XS_TWO_PI * (1.0 - frame.sun_cos_max); }

/** Uniform direction in the sun's cone; pdf = 1 / solid angle. */
vec3 xs_sun_sample(vec2 u)
{
    float ct = 1.0 - u.x * (1.0 - frame.sun_cos_max);
    float st = sqrt(max(0.0, 1.0 - ct * ct));
    float phi = XS_TWO_PI * u.y;
    vec3 n = frame.sun_direction.xyz, t, b;
    xs_onb(n, t, b);
    return normalize(t * (st * cos(phi)) + b * (st * sin(phi)) + n * ct);
}

/**
 * What a ray escaping along unit dir sees, weighted for MIS when it was BSDF-sampled with
 * solid-angle pdf prev_pdf (prev_delta: a camera ray or a delta lobe, weight 1). Without a map
 * and sun disk this is the constant environment, as before the map existed.
 */
vec3 xs_env_escape(vec3 dir, bool prev_delta, float prev_pdf)
{
    vec3 l = frame.environment.rgb;
    if (frame.env_width > 0u) {
        l = xs_env_radiance(dir);
        if (!prev_delta && frame.env_sampling != 0u)
            l *= xs_mis_power(prev_pdf, xs_env_pdf(dir));
    }
    if (frame.sun_direction.w > 0.0 && frame.sun_cos_max > 0.0 &&
        dot(dir, frame.sun_direction.xyz) >= frame.sun_cos_max) {
        float omega = xs_sun_solid_angle();
        float w = prev_delta ? 1.0 : xs_mis_power(prev_pdf, 1.0 / omega);
        l += frame.sun_radiance.rgb * (w / omega);
    }
    return l;
}

#endif
