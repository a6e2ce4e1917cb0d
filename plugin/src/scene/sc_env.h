// SPDX-License-Identifier: MIT
/**
 * @file sc_env.h
 * @brief Environment lighting on the CPU side: an equirectangular radiance map with the 2D
 *        distribution that importance-samples it, and the Preetham sun and sky baked into one.
 *
 * Map convention (shared with shaders/xs_env.glsl): rows top (+Y, zenith) to bottom (nadir);
 * the image centre (u = 0.5) looks down -Z, u grows towards +X. With rotation rho (radians,
 * about +Y, counter-clockwise seen from above) a world direction d is first turned by -rho.
 *   phi = atan2(d.x, -d.z), theta = acos(d.y), u = 0.5 + phi / 2pi, v = theta / pi.
 * Radiance is piecewise constant per texel (nearest lookup) and the sampling distribution is
 * exactly proportional to luminance x sin(theta at the row centre) per texel, uniform within
 * the texel in (u, v), so the solid-angle pdf is p_texel x W x H / (2 pi^2 sin theta)
 * (pbrt's infinite area light, adapted to nearest lookup).
 */
#pragma once

#include "xrsc/result.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/** A map ready for rendering. Arrays are malloc'ed; sc_env_map_free. */
typedef struct sc_env_map {
    uint32_t width, height; /**< 0 x 0: no map */
    /** width*height*4 floats: rgb radiance (intensity applied), a = p_texel x W x H / (2 pi^2),
     *  so the solid-angle pdf of a direction in that texel is a / sin(theta). */
    float *texels;
    float *marginal_cdf;    /**< height floats: inclusive prefix sums over rows, last = 1 */
    float *conditional_cdf; /**< width*height floats: per row, inclusive, last = 1 */
    bool sampling;          /**< false when the map is black (nothing to importance-sample) */
    float mean_radiance[3]; /**< solid-angle mean of the radiance */
} sc_env_map;

/**
 * Builds the map from w*h linear RGB floats (rows top to bottom), scaled by intensity.
 * Negative and non-finite values become 0. XRSC_ERROR_OUT_OF_MEMORY only.
 */
xrsc_result sc_env_map_build(const float *rgb, uint32_t w, uint32_t h, float intensity,
                             sc_env_map *out, xrsc_diag *diag);
void sc_env_map_free(sc_env_map *map);

/** Unit direction of map coordinates (u, v) in [0, 1]^2 (rotation applied). */
void sc_env_direction(float u, float v, float rotation_rad, float out_dir[3]);
/** Solid-angle pdf of sampling unit direction dir from the map (0 when !sampling). */
float sc_env_pdf(const sc_env_map *map, float rotation_rad, const float dir[3]);

/** Preetham et al. 1999 sky (seed 000 §5.1 lights bistro and san-miguel with it). */
typedef struct sc_sky_options {
    float sun_direction[3]; /**< unit, towards the sun; its elevation must be >= 0 */
    float turbidity;        /**< 0 means SC_SKY_DEFAULT_TURBIDITY; clamped to [1.7, 10] */
} sc_sky_options;

#define SC_SKY_DEFAULT_TURBIDITY 3.0f
/** Baked sky map size: the sky is smooth, so 256 x 128 texels (0.7 degrees) suffice. */
#define SC_SKY_WIDTH 256u
#define SC_SKY_HEIGHT 128u
/** Angular radius of the sun disk: 0.2665 degrees (half of the sun's 0.533 degrees). */
#define SC_SUN_ANGULAR_RADIUS_RAD 0.004651f
/** Radiance units: Preetham's luminance in kcd/m^2 times this (so the sun overhead gives a
 *  white Lambertian surface a radiance of about 1, near the range of the bundled scenes). */
#define SC_SKY_UNIT_SCALE 0.025f

/**
 * Bakes the sky into SC_SKY_WIDTH x SC_SKY_HEIGHT linear RGB floats (malloc'ed into
 * *out_rgb; rotation 0 convention above; below the horizon a ground of albedo
 * SC_SKY_GROUND_ALBEDO lit by sun and sky) and returns the sun's irradiance on a surface
 * facing it (rgb, after the atmosphere) in out_sun_irradiance.
 */
xrsc_result sc_sky_bake(const sc_sky_options *opt, float **out_rgb, float out_sun_irradiance[3],
                        xrsc_diag *diag);
#define SC_SKY_GROUND_ALBEDO 0.2f

/**
 * The built-in studio environment of a scene with no light (sc_scene.h): a sky gradient
 * (cool zenith, light horizon, darker warm ground, blended over a few degrees at the
 * horizon), a soft warm key light lobe above the default viewpoint's right shoulder
 * (SC_STUDIO_KEY_DIRECTION) and a dimmer, wider cool fill from the left, like the default
 * image-based lighting of glTF viewers. Normalised so that a white Lambertian plane facing
 * +Y reflects a radiance of SC_STUDIO_UP_RADIANCE (irradiance / pi over the texels).
 */
#define SC_STUDIO_WIDTH 256u
#define SC_STUDIO_HEIGHT 128u
#define SC_STUDIO_UP_RADIANCE 0.9f
/** Towards the key light (before normalisation): up 45 degrees, right and behind the default
 *  viewpoint (which looks down -Z), as SC_DEFAULT_SUN_DIRECTION. */
#define SC_STUDIO_KEY_DIRECTION {0.5f, 0.70710678f, 0.5f}
/** Towards the fill light (before normalisation): low on the left, in front of the model. */
#define SC_STUDIO_FILL_DIRECTION {-0.7f, 0.3f, 0.5f}
/** Bakes it into SC_STUDIO_WIDTH x SC_STUDIO_HEIGHT linear RGB floats (malloc'ed into
 *  *out_rgb, rotation 0 convention above). XRSC_ERROR_OUT_OF_MEMORY only. */
xrsc_result sc_studio_bake(float **out_rgb, xrsc_diag *diag);

#ifdef __cplusplus
}
#endif
