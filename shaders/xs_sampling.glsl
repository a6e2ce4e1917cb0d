// SPDX-License-Identifier: MIT
/**
 * @file xs_sampling.glsl
 * @brief Warps from [0,1)^2 to directions and triangles, an orthonormal basis, MIS weights.
 */
#ifndef XS_SAMPLING_GLSL
#define XS_SAMPLING_GLSL

#define XS_PI 3.14159265358979323846
#define XS_INV_PI 0.31830988618379067154
#define XS_TWO_PI 6.28318530717958647692

/** Orthonormal basis around unit n (Duff et al. 2017, "Building an Orthonormal Basis,
 *  Revisited", JCGT 6(1), Listing 3): branch-free except for the sign, no singularity. */
void xs_onb(vec3 n, out vec3 t, out vec3 b)
{
    float s = n.z >= 0.0 ? 1.0 : -1.0;
    float a = -1.0 / (s + n.z);
    float c = n.x * n.y * a;
    t = vec3(1.0 + s * n.x * n.x * a, s * c, -s * n.x);
    b = vec3(c, s + n.y * n.y * a, -n.y);
}

vec3 xs_to_local(vec3 v, vec3 t, vec3 b, vec3 n)
{
    return vec3(dot(v, t), dot(v, b), dot(v, n));
}

vec3 xs_to_world(vec3 v, vec3 t, vec3 b, vec3 n)
{
    return v.x * t + v.y * b + v.z * n;
}

/** Cosine-weighted hemisphere around +z (Malley's method): pdf = z / pi. */
vec3 xs_sample_cosine_hemisphere(vec2 u)
{
    float r = sqrt(u.x);
    float phi = XS_TWO_PI * u.y;
    return vec3(r * cos(phi), r * sin(phi), sqrt(max(0.0, 1.0 - u.x)));
}

/** Uniform point on a triangle as barycentrics (b1, b2) of vertices 1 and 2: the square-root
 *  warp (Pharr, Jakob, Humphreys, PBR 4th ed., §A.5.5), pdf = 1 / area. */
vec2 xs_sample_triangle(vec2 u)
{
    float su = sqrt(u.x);
    return vec2(u.y * su, 1.0 - su);
}

/** Power heuristic with beta = 2 (Veach 1997, §9.2.4), for one sample from each strategy. */
float xs_mis_power(float pdf_a, float pdf_b)
{
    float a = pdf_a * pdf_a;
    float b = pdf_b * pdf_b;
    return a + b > 0.0 ? a / (a + b) : 0.0;
}

float xs_max3(vec3 v)
{
    return max(v.x, max(v.y, v.z));
}

float xs_luminance(vec3 c)
{
    /* Rec. 709 / sRGB primaries luminance weights. */
    return dot(c, vec3(0.2126, 0.7152, 0.0722));
}

bool xs_finite(vec3 v)
{
    return !any(isnan(v)) && !any(isinf(v));
}

#endif
