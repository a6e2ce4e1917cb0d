// SPDX-License-Identifier: MIT
/**
 * @file xs_rng.glsl
 * @brief Deterministic hash-based random numbers: one PCG32 stream per (pixel, eye, frame,
 * sample, seed).
 *
 * Seeding chains the PCG output permutation used as a hash (Jarzynski and Olano 2020, "Hash
 * Functions for GPU Rendering", JCGT 9(3), pcg): h = hash(h + v) over seed, frame_index, eye,
 * pixel y, pixel x and sample index. Each step is a bijection of h for fixed v, so two streams
 * that differ in any one input start from different states. The stream then advances with the
 * PCG32 LCG (O'Neill 2014) and outputs the RXS-M-XS permutation of the state.
 */
#ifndef XS_RNG_GLSL
#define XS_RNG_GLSL

/* PCG32 LCG multiplier and increment (O'Neill 2014, the 32-bit default constants). */
#define XS_PCG_MULT 747796405u
#define XS_PCG_INC 2891336453u
/* RXS-M-XS output permutation multiplier (same source). */
#define XS_PCG_RXS_MULT 277803737u
/* 2^-24: turns the top 24 bits into a float in [0, 1) exactly. */
#define XS_INV_2POW24 5.9604644775390625e-8

uint xs_pcg_permute(uint state)
{
    uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * XS_PCG_RXS_MULT;
    return (word >> 22u) ^ word;
}

uint xs_hash(uint v)
{
    return xs_pcg_permute(v * XS_PCG_MULT + XS_PCG_INC);
}

struct xs_rng {
    uint state;
};

xs_rng xs_rng_seed(uvec2 pixel, uint eye, uint frame_index, uint sample_index, uint seed)
{
    uint h = xs_hash(seed);
    h = xs_hash(h + frame_index);
    h = xs_hash(h + eye);
    h = xs_hash(h + pixel.y);
    h = xs_hash(h + pixel.x);
    h = xs_hash(h + sample_index);
    xs_rng r;
    r.state = h;
    return r;
}

uint xs_rng_next_uint(inout xs_rng r)
{
    r.state = r.state * XS_PCG_MULT + XS_PCG_INC;
    return xs_pcg_permute(r.state);
}

/** Uniform in [0, 1). */
float xs_rng_next(inout xs_rng r)
{
    return float(xs_rng_next_uint(r) >> 8u) * XS_INV_2POW24;
}

vec2 xs_rng_next2(inout xs_rng r)
{
    float a = xs_rng_next(r);
    return vec2(a, xs_rng_next(r));
}

#endif
