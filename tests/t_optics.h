// SPDX-License-Identifier: MIT
/**
 * @file t_optics.h
 * @brief CPU reference optics of the GPU tests (double precision): what the shaders'
 *        dielectric Fresnel (xs_fresnel_dielectric) must equal.
 */
#ifndef T_OPTICS_H
#define T_OPTICS_H

#include <math.h>

/** Exact unpolarised Fresnel reflectance (cos_i on the incident side, eta = n_t / n_i);
 *  1 under total internal reflection. */
static inline double t_fresnel(double cos_i, double eta)
{
    double sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
    if (sin2_t >= 1.0)
        return 1.0;
    double cos_t = sqrt(1.0 - sin2_t);
    double rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    double rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    return 0.5 * (rs * rs + rp * rp);
}

#endif
