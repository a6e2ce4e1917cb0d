// SPDX-License-Identifier: MIT
/**
 * @file sc_env.c
 * @brief Environment map sampling tables and the Preetham sun and sky (sc_env.h).
 */
#include "sc_env.h"

#include "u_diag.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define SC_PI 3.14159265358979323846
/** Rec. 709 luminance weights (as sc_scene.c's emitter power). */
#define LUMA_R 0.2126
#define LUMA_G 0.7152
#define LUMA_B 0.0722

static double row_sin(uint32_t y, uint32_t h) { return sin(SC_PI * (y + 0.5) / h); }

xrsc_result sc_env_map_build(const float *rgb, uint32_t w, uint32_t h, float intensity,
                             sc_env_map *out, xrsc_diag *diag)
{
    memset(out, 0, sizeof(*out));
    size_t n = (size_t)w * h;
    out->texels = malloc(n * 4 * sizeof(float));
    out->marginal_cdf = malloc((size_t)h * sizeof(float));
    out->conditional_cdf = malloc(n * sizeof(float));
    double *row_sum = malloc((size_t)h * sizeof(double));
    if (!out->texels || !out->marginal_cdf || !out->conditional_cdf || !row_sum) {
        free(row_sum);
        sc_env_map_free(out);
        return u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, "", 0, "environment",
                          "out of memory for a %u x %u map", w, h);
    }
    out->width = w;
    out->height = h;
    double total = 0.0, mean[3] = {0, 0, 0}, solid = 0.0;
    for (uint32_t y = 0; y < h; y++) {
        double s = row_sin(y, h), sum = 0.0;
        for (uint32_t x = 0; x < w; x++) {
            size_t i = (size_t)y * w + x;
            float c[3];
            for (int k = 0; k < 3; k++) {
                float v = rgb[i * 3 + k] * intensity;
                c[k] = isfinite(v) && v > 0.0f ? v : 0.0f;
                out->texels[i * 4 + k] = c[k];
                mean[k] += c[k] * s;
            }
            /* weight: luminance x sin(theta) (the Jacobian of the equirectangular map) */
            sum += (LUMA_R * c[0] + LUMA_G * c[1] + LUMA_B * c[2]) * s;
            out->conditional_cdf[i] = (float)sum;
        }
        solid += s * w;
        for (uint32_t x = 0; x < w; x++) {
            size_t i = (size_t)y * w + x;
            /* a black row is never chosen; give it a uniform table all the same */
            out->conditional_cdf[i] =
                sum > 0.0 ? (float)(out->conditional_cdf[i] / sum) : (float)(x + 1) / w;
        }
        out->conditional_cdf[(size_t)y * w + w - 1] = 1.0f;
        row_sum[y] = sum;
        total += sum;
    }
    double acc = 0.0;
    for (uint32_t y = 0; y < h; y++) {
        acc += row_sum[y];
        out->marginal_cdf[y] = total > 0.0 ? (float)(acc / total) : (float)(y + 1) / h;
    }
    out->marginal_cdf[h - 1] = 1.0f;
    out->sampling = total > 0.0;
    /* a = p_texel x W x H / (2 pi^2) with p_texel = weight / total */
    double k = (double)w * h / (2.0 * SC_PI * SC_PI);
    for (uint32_t y = 0; y < h; y++) {
        double s = row_sin(y, h);
        for (uint32_t x = 0; x < w; x++) {
            size_t i = (size_t)y * w + x;
            const float *c = &out->texels[i * 4];
            double wt = (LUMA_R * c[0] + LUMA_G * c[1] + LUMA_B * c[2]) * s;
            out->texels[i * 4 + 3] = total > 0.0 ? (float)(wt / total * k) : 0.0f;
        }
    }
    for (int c = 0; c < 3; c++) out->mean_radiance[c] = solid > 0.0 ? (float)(mean[c] / solid) : 0;
    free(row_sum);
    return XRSC_OK;
}

void sc_env_map_free(sc_env_map *map)
{
    if (!map) return;
    free(map->texels);
    free(map->marginal_cdf);
    free(map->conditional_cdf);
    memset(map, 0, sizeof(*map));
}

void sc_env_direction(float u, float v, float rotation_rad, float out_dir[3])
{
    double phi = (u - 0.5) * 2.0 * SC_PI + rotation_rad, theta = v * SC_PI;
    out_dir[0] = (float)(sin(theta) * sin(phi));
    out_dir[1] = (float)cos(theta);
    out_dir[2] = (float)(-sin(theta) * cos(phi));
}

float sc_env_pdf(const sc_env_map *map, float rotation_rad, const float dir[3])
{
    if (!map->sampling) return 0.0f;
    double phi = atan2(dir[0], -dir[2]) - rotation_rad;
    double u = 0.5 + phi / (2.0 * SC_PI);
    u -= floor(u);
    double cy = dir[1] < -1.0f ? -1.0 : dir[1] > 1.0f ? 1.0 : dir[1];
    double theta = acos(cy), s = sin(theta);
    if (s <= 0.0) return 0.0f;
    uint32_t x = (uint32_t)(u * map->width), y = (uint32_t)(theta / SC_PI * map->height);
    if (x >= map->width) x = map->width - 1;
    if (y >= map->height) y = map->height - 1;
    return (float)(map->texels[((size_t)y * map->width + x) * 4 + 3] / s);
}

/* ---- Preetham, Shirley, Smits 1999, "A practical analytic model for daylight" ---- */

/** Perez et al. distribution coefficients A..E as linear functions of turbidity T (Preetham
 *  1999, Appendix A.2): {slope, offset} for luminance Y and chromaticities x, y. */
static const double perez_Y[5][2] = {
    {0.1787, -1.4630}, {-0.3554, 0.4275}, {-0.0227, 5.3251}, {0.1206, -2.5771}, {-0.0670, 0.3703}};
static const double perez_x[5][2] = {
    {-0.0193, -0.2592}, {-0.0665, 0.0008}, {-0.0004, 0.2125}, {-0.0641, -0.8989}, {-0.0033, 0.0452}};
static const double perez_y[5][2] = {
    {-0.0167, -0.2608}, {-0.0950, 0.0092}, {-0.0079, 0.2102}, {-0.0441, -1.6537}, {-0.0109, 0.0529}};
/** Zenith chromaticity polynomials (Appendix A.2): [T^2, T, 1] x M x [ts^3, ts^2, ts, 1]. */
static const double zenith_x[3][4] = {{0.00166, -0.00375, 0.00209, 0.0},
                                      {-0.02903, 0.06377, -0.03202, 0.00394},
                                      {0.11693, -0.21196, 0.06052, 0.25886}};
static const double zenith_y[3][4] = {{0.00275, -0.00610, 0.00317, 0.0},
                                      {-0.04214, 0.08970, -0.04153, 0.00516},
                                      {0.15346, -0.26756, 0.06670, 0.26688}};

typedef struct perez { double a, b, c, d, e; } perez;

static perez perez_of(const double k[5][2], double t)
{
    return (perez){k[0][0] * t + k[0][1], k[1][0] * t + k[1][1], k[2][0] * t + k[2][1],
                   k[3][0] * t + k[3][1], k[4][0] * t + k[4][1]};
}

/** F(theta, gamma) = (1 + A e^(B / cos theta)) (1 + C e^(D gamma) + E cos^2 gamma). */
static double perez_f(perez p, double cos_theta, double gamma)
{
    double ct = cos_theta < 1e-3 ? 1e-3 : cos_theta, cg = cos(gamma);
    return (1.0 + p.a * exp(p.b / ct)) * (1.0 + p.c * exp(p.d * gamma) + p.e * cg * cg);
}

static double zenith_chroma(const double m[3][4], double t, double ts)
{
    double tv[3] = {t * t, t, 1.0}, sv[4] = {ts * ts * ts, ts * ts, ts, 1.0}, r = 0.0;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 4; j++) r += tv[i] * m[i][j] * sv[j];
    return r;
}

/** CIE xyY → linear Rec. 709 / sRGB (D65). */
static void xyY_to_rgb(double x, double y, double Y, float out[3])
{
    double X = y > 0.0 ? x / y * Y : 0.0, Z = y > 0.0 ? (1.0 - x - y) / y * Y : 0.0;
    double r = 3.2406 * X - 1.5372 * Y - 0.4986 * Z;
    double g = -0.9689 * X + 1.8758 * Y + 0.0415 * Z;
    double b = 0.0557 * X - 0.2040 * Y + 1.0570 * Z;
    out[0] = (float)(r > 0.0 ? r : 0.0);
    out[1] = (float)(g > 0.0 ? g : 0.0);
    out[2] = (float)(b > 0.0 ? b : 0.0);
}

/** Extraterrestrial solar illuminance, klux (Preetham's units for the sky are kcd/m^2). */
#define SUN_ILLUMINANCE_KLUX 127.5
/** Wavelengths (micrometres) standing for the R, G, B channels in the transmittance. */
static const double channel_um[3] = {0.610, 0.550, 0.465};
/** Angstrom exponent of the aerosol (Preetham 1999, Appendix A.1). */
#define AEROSOL_ALPHA 1.3

/** Sun irradiance after Rayleigh and aerosol extinction (Preetham 1999, Appendix A.1, ozone,
 *  mixed gases and water vapour left out); relative optical mass by Kasten's formula. */
static void sun_irradiance(double theta_s, double t, float out[3])
{
    double deg = theta_s * 180.0 / SC_PI;
    double m = 1.0 / (cos(theta_s) + 0.15 * pow(93.885 - deg, -1.253));
    double beta = 0.04608 * t - 0.04586;
    for (int c = 0; c < 3; c++) {
        double l = channel_um[c];
        double tr = exp(-0.008735 * pow(l, -4.08) * m);
        double ta = exp(-beta * pow(l, -AEROSOL_ALPHA) * m);
        out[c] = (float)(SC_SKY_UNIT_SCALE * SUN_ILLUMINANCE_KLUX * tr * ta);
    }
}

xrsc_result sc_sky_bake(const sc_sky_options *opt, float **out_rgb, float out_sun_irradiance[3],
                        xrsc_diag *diag)
{
    *out_rgb = NULL;
    const float *sd = opt->sun_direction;
    double len = sqrt((double)sd[0] * sd[0] + (double)sd[1] * sd[1] + (double)sd[2] * sd[2]);
    if (!(len > 0.0) || sd[1] / len < 0.0)
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "sun direction",
                          "the sun must be at or above the horizon (y >= 0) for the sky");
    double sun[3] = {sd[0] / len, sd[1] / len, sd[2] / len};
    double t = opt->turbidity > 0.0f ? opt->turbidity : SC_SKY_DEFAULT_TURBIDITY;
    t = t < 1.7 ? 1.7 : t > 10.0 ? 10.0 : t;
    double ts = acos(sun[1]);
    perez pY = perez_of(perez_Y, t), px = perez_of(perez_x, t), py = perez_of(perez_y, t);
    /* zenith luminance (kcd/m^2) and chromaticity (Appendix A.2) */
    double chi = (4.0 / 9.0 - t / 120.0) * (SC_PI - 2.0 * ts);
    double Yz = (4.0453 * t - 4.9710) * tan(chi) - 0.2155 * t + 2.4192;
    double xz = zenith_chroma(zenith_x, t, ts), yz = zenith_chroma(zenith_y, t, ts);
    double fY = perez_f(pY, 1.0, ts), fx = perez_f(px, 1.0, ts), fy = perez_f(py, 1.0, ts);

    const uint32_t w = SC_SKY_WIDTH, h = SC_SKY_HEIGHT;
    float *rgb = malloc((size_t)w * h * 3 * sizeof(float));
    if (!rgb)
        return u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, "", 0, "sky", "out of memory");
    double e_sky = 0.0, d_omega = (2.0 * SC_PI / w) * (SC_PI / h);
    for (uint32_t y = 0; y < h / 2; y++) {
        for (uint32_t x = 0; x < w; x++) {
            float d[3];
            sc_env_direction((x + 0.5f) / w, (y + 0.5f) / h, 0.0f, d);
            double cg = d[0] * sun[0] + d[1] * sun[1] + d[2] * sun[2];
            double gamma = acos(cg < -1.0 ? -1.0 : cg > 1.0 ? 1.0 : cg);
            double Y = Yz * perez_f(pY, d[1], gamma) / fY * SC_SKY_UNIT_SCALE;
            double cx = xz * perez_f(px, d[1], gamma) / fx, cy = yz * perez_f(py, d[1], gamma) / fy;
            float *o = &rgb[((size_t)y * w + x) * 3];
            xyY_to_rgb(cx, cy, Y > 0.0 ? Y : 0.0, o);
            e_sky += (LUMA_R * o[0] + LUMA_G * o[1] + LUMA_B * o[2]) * d[1] * d_omega *
                     row_sin(y, h);
        }
    }
    sun_irradiance(ts, t, out_sun_irradiance);
    /* the ground: Lambertian, albedo SC_SKY_GROUND_ALBEDO, lit by the sun and the sky (grey) */
    for (uint32_t y = h / 2; y < h; y++)
        for (uint32_t x = 0; x < w; x++)
            for (int c = 0; c < 3; c++)
                rgb[((size_t)y * w + x) * 3 + c] =
                    (float)(SC_SKY_GROUND_ALBEDO / SC_PI *
                            (out_sun_irradiance[c] * sun[1] + e_sky));
    *out_rgb = rgb;
    return XRSC_OK;
}

/* ---- the built-in studio environment (sc_env.h) ---- */

/** Sky gradient colours (relative; the whole map is normalised afterwards). */
static const double studio_zenith[3] = {0.62, 0.68, 0.80};
static const double studio_horizon[3] = {0.90, 0.90, 0.88};
static const double studio_ground[3] = {0.34, 0.32, 0.30};
/** Half-width (as sin of elevation) of the blend between sky and ground at the horizon. */
#define STUDIO_HORIZON_BLEND 0.05
/** Lobes exp(kappa (cos gamma - 1)): solid angle about 2 pi / kappa. Key: about 10 degrees
 *  wide, carrying about 1.5 times the sky's irradiance on an upward plane; fill: wider and
 *  dimmer, lifting the shadow side. Peak radiances relative to the sky's. */
#define STUDIO_KEY_KAPPA 40.0
#define STUDIO_KEY_PEAK 28.0
#define STUDIO_FILL_KAPPA 8.0
#define STUDIO_FILL_PEAK 1.2
static const double studio_key_color[3] = {1.00, 0.92, 0.80};
static const double studio_fill_color[3] = {0.80, 0.88, 1.00};

static void unit3d(const float in[3], double out[3])
{
    double l = sqrt((double)in[0] * in[0] + (double)in[1] * in[1] + (double)in[2] * in[2]);
    for (int k = 0; k < 3; k++) out[k] = in[k] / l;
}

static double studio_smoothstep(double e0, double e1, double x)
{
    double t = (x - e0) / (e1 - e0);
    t = t < 0.0 ? 0.0 : t > 1.0 ? 1.0 : t;
    return t * t * (3.0 - 2.0 * t);
}

/** Relative studio radiance towards unit direction d. */
static void studio_radiance(const float d[3], const double key[3], const double fill[3],
                            float out[3])
{
    double y = d[1], up = y > 0.0 ? sqrt(y) : 0.0, down = y < 0.0 ? sqrt(-y) : 0.0;
    double g = studio_smoothstep(-STUDIO_HORIZON_BLEND, STUDIO_HORIZON_BLEND, y);
    double ck = d[0] * key[0] + d[1] * key[1] + d[2] * key[2];
    double cf = d[0] * fill[0] + d[1] * fill[1] + d[2] * fill[2];
    double lk = STUDIO_KEY_PEAK * exp(STUDIO_KEY_KAPPA * (ck - 1.0));
    double lf = STUDIO_FILL_PEAK * exp(STUDIO_FILL_KAPPA * (cf - 1.0));
    for (int c = 0; c < 3; c++) {
        double sky = studio_horizon[c] + (studio_zenith[c] - studio_horizon[c]) * up;
        double ground = studio_ground[c] * (1.0 - 0.3 * down);
        out[c] = (float)(ground + (sky - ground) * g + lk * studio_key_color[c] +
                         lf * studio_fill_color[c]);
    }
}

xrsc_result sc_studio_bake(float **out_rgb, xrsc_diag *diag)
{
    const uint32_t w = SC_STUDIO_WIDTH, h = SC_STUDIO_HEIGHT;
    static const float key_dir[3] = SC_STUDIO_KEY_DIRECTION, fill_dir[3] = SC_STUDIO_FILL_DIRECTION;
    double key[3], fill[3];
    unit3d(key_dir, key);
    unit3d(fill_dir, fill);
    float *rgb = malloc((size_t)w * h * 3 * sizeof(float));
    *out_rgb = NULL;
    if (!rgb)
        return u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, "", 0, "environment", "out of memory");
    /* irradiance on a plane facing +Y over the texels (the renderer's piecewise constant map) */
    double e_up = 0.0, d_omega = (2.0 * SC_PI / w) * (SC_PI / h);
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++) {
            float d[3];
            sc_env_direction((x + 0.5f) / w, (y + 0.5f) / h, 0.0f, d);
            float *o = &rgb[((size_t)y * w + x) * 3];
            studio_radiance(d, key, fill, o);
            if (d[1] > 0.0f)
                e_up += (LUMA_R * o[0] + LUMA_G * o[1] + LUMA_B * o[2]) * d[1] * d_omega *
                        row_sin(y, h);
        }
    double k = SC_STUDIO_UP_RADIANCE * SC_PI / e_up;
    for (size_t i = 0; i < (size_t)w * h * 3; i++) rgb[i] = (float)(rgb[i] * k);
    *out_rgb = rgb;
    return XRSC_OK;
}
