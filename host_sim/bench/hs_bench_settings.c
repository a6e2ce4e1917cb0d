// SPDX-License-Identifier: MIT
/**
 * @file hs_bench_settings.c
 * @brief `xrsc bench` settings: "METHOD[:KEY=VALUE,...]" texts to renderer options.
 *
 * Every setting dimension is one row of `keys` below: its name, the methods it applies to and
 * a function that writes the value into xrsc_renderer_options. A new renderer option is
 * benchmarked by adding a row. The key "r" (the stereo blend's R) is also recorded as the
 * setting's R for the stereo-vs-R chart (hs_bench_setting.r / .group).
 */
#include "hs_bench.h"

#include "hs_args.h"
#include "hs_replay.h"
#include "u_diag.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define M_SPP (1u << XRSC_METHOD_SPP)
#define M_PRIMARY (1u << XRSC_METHOD_PRIMARY)
#define M_SC (1u << XRSC_METHOD_SAMPLECACHE)
#define M_TAA (1u << XRSC_METHOD_TAA)
#define M_HC (1u << XRSC_METHOD_HASHCACHE)
#define M_HY (1u << XRSC_METHOD_HYBRID)
#define M_ISRT (1u << XRSC_METHOD_ISRT)
#define M_ALL ((1u << XRSC_METHOD_COUNT) - 1u)

static bool parse_u32(const char *s, uint32_t lo, uint32_t hi, uint32_t *out)
{
    char *end;
    errno = 0;
    unsigned long v = strtoul(s, &end, 10);
    if (errno || end == s || *end || s[0] == '-' || v < lo || v > hi)
        return false;
    *out = (uint32_t)v;
    return true;
}

static bool parse_pos(const char *s, double max, float *out)
{
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (errno || end == s || *end || !(v > 0) || v > max)
        return false;
    *out = (float)v;
    return true;
}

/* Each setter returns NULL or the accepted values (for the message). */
static const char *set_spp(xrsc_renderer_options *o, const char *v)
{
    return parse_u32(v, 1, 4096, &o->spp.samples_per_pixel) ? NULL : "1..4096";
}

static const char *set_bounces(xrsc_renderer_options *o, const char *v)
{
    uint32_t u;
    if (!parse_u32(v, 0, 16, &u))
        return "0..16";
    o->spp.max_bounces = o->samplecache.max_bounces = u ? u : XRSC_BOUNCES_NONE;
    o->hashcache.max_bounces = o->spp.max_bounces;
    return NULL;
}

static const char *set_trace(xrsc_renderer_options *o, const char *v)
{
    if (!strcmp(v, "single"))
        o->samplecache.trace = XRSC_SC_TRACE_SINGLE;
    else if (!strcmp(v, "multi"))
        o->samplecache.trace = XRSC_SC_TRACE_MULTI;
    else if (!strcmp(v, "adaptive"))
        o->samplecache.trace = XRSC_SC_TRACE_ADAPTIVE;
    else
        return "single, multi, adaptive";
    return NULL;
}

static const char *set_reproject(xrsc_renderer_options *o, const char *v)
{
    if (!strcmp(v, "1pass"))
        o->samplecache.reproject = XRSC_SC_REPROJECT_1PASS;
    else if (!strcmp(v, "2pass"))
        o->samplecache.reproject = XRSC_SC_REPROJECT_2PASS;
    else
        return "1pass, 2pass";
    return NULL;
}

static const char *set_shading_cache(xrsc_renderer_options *o, const char *v)
{
    bool on;
    if (!hs_parse_on_off(v, &on))
        return "on, off";
    o->samplecache.no_shading_cache = !on;
    return NULL;
}

static const char *set_shade(xrsc_renderer_options *o, const char *v)
{
    if (!strcmp(v, "uniform"))
        o->samplecache.shade = XRSC_SC_SHADE_UNIFORM;
    else if (!strcmp(v, "adaptive"))
        o->samplecache.shade = XRSC_SC_SHADE_ADAPTIVE;
    else if (!strcmp(v, "adaptive-variance"))
        o->samplecache.shade = XRSC_SC_SHADE_ADAPTIVE_VARIANCE;
    else
        return "uniform, adaptive, adaptive-variance";
    return NULL;
}

static const char *set_cross_eye(xrsc_renderer_options *o, const char *v)
{
    return hs_parse_on_off(v, &o->samplecache.cross_eye) ? NULL : "on, off";
}

static const char *set_stratify(xrsc_renderer_options *o, const char *v)
{
    return hs_parse_on_off(v, &o->samplecache.stratify) ? NULL : "on, off";
}

static const char *set_alpha(xrsc_renderer_options *o, const char *v)
{
    if (!strcmp(v, "clamped"))
        o->samplecache.alpha = XRSC_SC_ALPHA_CLAMPED;
    else if (!strcmp(v, "fixed"))
        o->samplecache.alpha = XRSC_SC_ALPHA_FIXED;
    else
        return "clamped, fixed";
    return NULL;
}

static const char *set_slots(xrsc_renderer_options *o, const char *v)
{
    return parse_u32(v, 1, 16, &o->samplecache.slots) ? NULL : "1..16";
}

static const char *set_block(xrsc_renderer_options *o, const char *v)
{
    return parse_u32(v, 1, 64, &o->samplecache.block) ? NULL : "1..64";
}

static const char *set_target(xrsc_renderer_options *o, const char *v)
{
    return parse_pos(v, 16, &o->samplecache.n_target) ? NULL : "(0, 16]";
}

static const char *set_delta(xrsc_renderer_options *o, const char *v)
{
    return parse_pos(v, 16, &o->samplecache.delta) ? NULL : "(0, 16]";
}

static const char *set_eps0(xrsc_renderer_options *o, const char *v)
{
    return parse_pos(v, 1, &o->samplecache.eps0) ? NULL : "(0, 1]";
}

static const char *set_eps1(xrsc_renderer_options *o, const char *v)
{
    return parse_pos(v, 1, &o->samplecache.eps1) ? NULL : "(0, 1]";
}

static const char *set_moving(xrsc_renderer_options *o, const char *v)
{
    return hs_parse_on_off(v, &o->samplecache.moving) ? NULL : "on, off";
}

static const char *set_cover(xrsc_renderer_options *o, const char *v)
{
    return hs_parse_on_off(v, &o->samplecache.cover) ? NULL : "on, off";
}

static const char *set_firefly(xrsc_renderer_options *o, const char *v)
{
    if (!strcmp(v, "off")) {
        o->samplecache.firefly_clamp = 0.0f;
        return NULL;
    }
    float k;
    if (!parse_pos(v, 1e6, &k) || k < 1.0f)
        return "off or k in [1, 1e6]";
    o->samplecache.firefly_clamp = k;
    return NULL;
}

static const char *set_shade_rate(xrsc_renderer_options *o, const char *v)
{
    if (!parse_pos(v, 1600, &o->samplecache.shade_rate))
        return "percent in (0, 1600]";
    o->samplecache.shade_rate *= 0.01f;
    return NULL;
}

static const char *set_alpha_fixed(xrsc_renderer_options *o, const char *v)
{
    return parse_pos(v, 1, &o->samplecache.alpha_fixed) ? NULL : "(0, 1]";
}

static const char *set_vis_cache(xrsc_renderer_options *o, const char *v)
{
    return hs_parse_on_off(v, &o->samplecache.visibility.enabled) ? NULL : "on, off";
}

static const char *set_vis_tolerance(xrsc_renderer_options *o, const char *v)
{
    return parse_pos(v, 1024, &o->samplecache.visibility.error_px) ? NULL : "pixels in (0, 1024]";
}

static const char *set_vis_refine(xrsc_renderer_options *o, const char *v)
{
    static const char *const names[] = {"adaptive", "strict", "none"};
    for (uint32_t i = 0; i < 3; i++)
        if (!strcmp(v, names[i])) {
            o->samplecache.visibility.refine = (xrsc_sc_vis_refine)(XRSC_SC_VIS_REFINE_ADAPTIVE + i);
            return NULL;
        }
    return "adaptive, strict, none";
}

static const char *set_isrt_m(xrsc_renderer_options *o, const char *v)
{
    return parse_u32(v, 1, 4, &o->isrt.m) ? NULL : "1..4";
}

static const char *set_hc_table(xrsc_renderer_options *o, const char *v)
{
    return parse_u32(v, 16, 1u << 27, &o->hashcache.table_entries) ? NULL : "16..134217728";
}

static const char *set_hc_lod(xrsc_renderer_options *o, const char *v)
{
    if (!strcmp(v, "distance"))
        o->hashcache.lod = XRSC_HC_LOD_DISTANCE;
    else if (!strcmp(v, "distance-normal"))
        o->hashcache.lod = XRSC_HC_LOD_DISTANCE_NORMAL;
    else
        return "distance, distance-normal";
    return NULL;
}

static const char *set_hc_voxel_scale(xrsc_renderer_options *o, const char *v)
{
    return parse_pos(v, 1024, &o->hashcache.voxel_scale) ? NULL : "(0, 1024]";
}

static const char *set_hc_max_age(xrsc_renderer_options *o, const char *v)
{
    return parse_u32(v, 1, UINT32_MAX, &o->hashcache.max_age) ? NULL : "frames >= 1";
}

static const char *set_hc_voxel_jitter(xrsc_renderer_options *o, const char *v)
{
    bool on;
    if (!hs_parse_on_off(v, &on))
        return "on, off";
    o->hashcache.no_voxel_jitter = !on;
    return NULL;
}

static const char *set_blend(xrsc_renderer_options *o, const char *v)
{
    return xrsc_blend_from_name(v, &o->blend) == XRSC_OK ? NULL : "none, pfj23, moments";
}

static const char *set_blend_estimate(xrsc_renderer_options *o, const char *v)
{
    return xrsc_blend_estimate_from_name(v, &o->blend_estimate) == XRSC_OK ? NULL
                                                                            : "samples, mean";
}

static const char *set_taa(xrsc_renderer_options *o, const char *v)
{
    if (!strcmp(v, "default") ||
        xrsc_taa_mode_from_name(v, &o->taa.mode) != XRSC_OK)
        return "off, on, pfj23";
    return NULL;
}

static const char *set_taa_alpha(xrsc_renderer_options *o, const char *v)
{
    return parse_pos(v, 1, &o->taa.alpha) ? NULL : "(0, 1]";
}

static const char *set_taa_history(xrsc_renderer_options *o, const char *v)
{
    if (!strcmp(v, "default") || xrsc_taa_history_from_name(v, &o->taa.history) != XRSC_OK)
        return "bilinear, catmull-rom";
    return NULL;
}

static const char *set_taa_motion(xrsc_renderer_options *o, const char *v)
{
    if (!strcmp(v, "default") || xrsc_taa_motion_from_name(v, &o->taa.motion) != XRSC_OK)
        return "off, on, edges";
    return NULL;
}

static const char *set_taa_motion_px2(xrsc_renderer_options *o, const char *v)
{
    return parse_pos(v, 16, &o->taa.motion_px2) ? NULL : "(0, 16]";
}

static const char *set_taa_motion_alpha(xrsc_renderer_options *o, const char *v)
{
    return parse_pos(v, 1, &o->taa.motion_alpha) ? NULL : "(0, 1]";
}

static const char *set_blend_inst(xrsc_renderer_options *o, const char *v)
{
    return hs_parse_on_off(v, &o->blend_instance_test) ? NULL : "on, off";
}

static const char *set_r(xrsc_renderer_options *o, const char *v)
{
    char *end;
    errno = 0;
    double d = strtod(v, &end);
    if (errno || end == v || *end || !(d >= 0.0 && d <= 1.0))
        return "R in [0, 1]";
    o->blend_r = (float)d;
    return NULL;
}

typedef struct bench_key {
    const char *key;
    uint32_t methods; /**< bit per xrsc_method */
    const char *(*set)(xrsc_renderer_options *o, const char *value);
    const char *short_name; /**< in derived labels ("" = the value alone, NULL = key=value) */
    const char *help;
} bench_key;

/* The setting dimensions. Add renderer options here. */
static const bench_key keys[] = {
    {"blend", M_SPP | M_PRIMARY | M_SC | M_ISRT | M_HC | M_HY, set_blend, "",
     "stereo blend none | pfj23 | moments (moments: spp, samplecache, isrt, hybrid) [none]"},
    {"blend_inst", M_SPP | M_PRIMARY | M_SC | M_ISRT | M_HC | M_HY, set_blend_inst, "bi",
     "stereo blend taps must show the pixel's instance (hit id) too, on | off [off; default: on]"},
    {"r", M_SPP | M_PRIMARY | M_SC | M_ISRT | M_HY, set_r, "r",
     "sharpness R of the moments blend, [0, 1] [0]"},
    {"estimate", M_SPP | M_PRIMARY | M_SC | M_ISRT | M_HY, set_blend_estimate, "est",
     "variances of the moments blend: samples (Eq. 5 as printed) | mean (of the pixel) "
     "[samples]"},
    {"taa", M_ALL, set_taa, "taa",
     "TAA post-pass off | on | pfj23 [on for taa, pfj23 for hashcache/hybrid, else off]"},
    {"taa_alpha", M_ALL, set_taa_alpha, "ta",
     "weight of the current frame with taa=on, (0, 1] [0.1]"},
    {"taa_history", M_ALL, set_taa_history, "",
     "TAA history resampling bilinear | catmull-rom [bilinear]"},
    {"taa_motion", M_ALL, set_taa_motion, "tm", "TAA motion rule (taa=on) off | on | edges [off; default: edges]"},
    {"taa_motion_px2", M_ALL, set_taa_motion_px2, "tmb",
     "resampling blur (px^2) at which the TAA motion rule reaches its highest weight, "
     "(0, 16] [0.25]"},
    {"taa_motion_alpha", M_ALL, set_taa_motion_alpha, "tma",
     "the TAA motion rule's highest weight of the current frame, (0, 1] [0.5]"},
    {"spp", M_SPP, set_spp, "", "samples per pixel per frame, 1..4096 [1]"},
    {"bounces", M_SPP | M_SC | M_ISRT | M_HC | M_HY, set_bounces, "b", "bounces after the first hit, 0..16 [3]"},
    {"trace", M_SC | M_ISRT | M_HY, set_trace, "", "single | multi | adaptive [adaptive]"},
    {"reproject", M_SC | M_HY, set_reproject, "", "1pass | 2pass [1pass]"},
    {"slots", M_SC | M_HY, set_slots, "n", "slots per pixel, 1..16 [12]"},
    {"target", M_SC | M_HY, set_target, "t", "target samples per pixel [4]"},
    {"delta", M_SC | M_HY, set_delta, "d", "density tolerance [1]"},
    {"eps0", M_SC | M_ISRT | M_HY, set_eps0, "e0", "retrace tolerance (relative) [0.001]"},
    {"eps1", M_SC | M_ISRT | M_HY, set_eps1, "e1", "edge test epsilon (Eq. 2) [0.005]"},
    {"block", M_SC | M_ISRT | M_HY, set_block, "blk", "base-rate block size [4]"},
    {"shading_cache", M_SC | M_ISRT, set_shading_cache, "shc", "on | off [on]"},
    {"shade", M_SC | M_ISRT, set_shade, "shade",
     "uniform | adaptive | adaptive-variance [uniform; default: adaptive-variance]"},
    {"shade_rate", M_SC | M_ISRT, set_shade_rate, "rate",
     "adaptive shading rate, percent [100; default: " HS_REPLAY_DEFAULT_SHADE_PERCENT_STR " unless shade is given]"},
    {"alpha", M_SC | M_ISRT, set_alpha, "alpha", "clamped | fixed [clamped]"},
    {"alpha_fixed", M_SC | M_ISRT, set_alpha_fixed, "af", "alpha of alpha=fixed [0.1]"},
    {"cross_eye", M_SC, set_cross_eye, "xeye",
     "on | off: view-independent samples serve both eyes, shaded once [off]"},
    {"stratify", M_SC, set_stratify, "strat",
     "on | off: new samples fill the pixel's emptiest strata [off]"},
    {"firefly", M_SC | M_ISRT, set_firefly, "ff",
     "firefly rule: cap a shading at k x the sample's running mean, off | k >= 1 [off]"},
    {"moving", M_SC, set_moving, "mov",
     "moving-sample rule: a pixel with samples on a turning instance shades one more, "
     "turning faces keep a short history, on | off [off; default: on]"},
    {"cover", M_SC, set_cover, "cov",
     "cover rule (variance-guided shading): a pixel with samples but none shaded shades one, "
     "on | off [off; default: on]"},
    {"vis_cache", M_SC | M_ISRT, set_vis_cache, "vc",
     "shading pass's shadow visibility cache (seed 002) on | off [off]"},
    {"vis_tolerance", M_SC | M_ISRT, set_vis_tolerance, "ce",
     "visibility cache error threshold C_E, pixels [4]"},
    {"vis_refine", M_SC | M_ISRT, set_vis_refine, "",
     "visibility cache refinement adaptive | strict | none [adaptive]"},
    {"m", M_ISRT, set_isrt_m, "m", "isrt: M x M fixed sub-pixel slots per pixel, 1..4 [2]"},
    {"hc_table", M_HC | M_HY, set_hc_table, "tab", "hash cache entries, 16..2^27 [4194304]"},
    {"hc_lod", M_HC | M_HY, set_hc_lod, "", "voxel LoD distance | distance-normal [distance]"},
    {"hc_voxel_scale", M_HC | M_HY, set_hc_voxel_scale, "vs",
     "voxel edge / pixel footprint [0.5]"},
    {"hc_max_age", M_HC | M_HY, set_hc_max_age, "age",
     "frames before an unaccessed entry may be overwritten [64]"},
    {"hc_voxel_jitter", M_HC | M_HY, set_hc_voxel_jitter, "vj", "on | off [on]"},
};
#define KEY_COUNT (sizeof(keys) / sizeof(keys[0]))

void hs_bench_print_keys(FILE *f)
{
    fprintf(f, "  method %s: what `xrsc replay` renders without options (%s and\n"
               "  its default blend and temporal filter); the keys of %s apply\n",
            HS_BENCH_DEFAULT_SETTING, xrsc_method_name(XRSC_METHOD_SAMPLECACHE),
            xrsc_method_name(XRSC_METHOD_SAMPLECACHE));
    fprintf(f, "  name=LABEL          label (file name; default derived from the keys)\n");
    for (size_t k = 0; k < KEY_COUNT; k++) {
        char methods[64] = "";
        for (int m = 0; m < XRSC_METHOD_COUNT; m++)
            if (keys[k].methods & (1u << m))
                snprintf(methods + strlen(methods), sizeof(methods) - strlen(methods), "%s%s",
                         methods[0] ? "," : "", xrsc_method_name((xrsc_method)m));
        fprintf(f, "  %-18s  %-16s %s\n", keys[k].key, methods, keys[k].help);
    }
}

static bool valid_name(const char *s)
{
    if (!s[0] || strlen(s) >= HS_BENCH_NAME_MAX)
        return false;
    for (const char *p = s; *p; p++)
        if (!((*p >= 'a' && *p <= 'z') || (*p >= 'A' && *p <= 'Z') || (*p >= '0' && *p <= '9') ||
              *p == '.' || *p == '_' || *p == '+' || *p == '-'))
            return false;
    return true;
}

static void trim(char **s)
{
    while (**s == ' ' || **s == '\t' || **s == '\n' || **s == '\r')
        (*s)++;
    char *e = *s + strlen(*s);
    while (e > *s && (e[-1] == ' ' || e[-1] == '\t' || e[-1] == '\n' || e[-1] == '\r'))
        *--e = '\0';
}

static void append(char *dst, size_t cap, const char *sep, const char *text)
{
    size_t n = strlen(dst);
    if (n < cap && snprintf(dst + n, cap - n, "%s%s", n ? sep : "", text) >= (int)(cap - n))
        dst[cap - 1] = '\0'; /* truncated: labels and specs are limited in length */
}

/* Parses one "METHOD[:k=v,...]" (modifiable copy) into s. */
static xrsc_result parse_one(char *text, hs_bench_setting *s, xrsc_diag *diag)
{
    memset(s, 0, sizeof(*s));
    s->r = NAN;
    char *colon = strchr(text, ':');
    char *args = NULL;
    if (colon) {
        *colon = '\0';
        args = colon + 1;
    }
    char *method = text;
    trim(&method);
    /* "default": what `xrsc replay` renders without options (its method, blend and TAA), from the
     * replay's own defaults (hs_replay_default_renderer), so a chart's default is the product */
    bool product = !strcmp(method, HS_BENCH_DEFAULT_SETTING);
    if (product)
        hs_replay_default_renderer(&s->renderer);
    else if (xrsc_method_from_name(method, &s->renderer.method) != XRSC_OK)
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "--settings",
                          "unknown method '%s' (xrsc --help lists them)", method);
    snprintf(s->spec, sizeof(s->spec), "%s", method);
    snprintf(s->group, sizeof(s->group), "%s", method);
    char label[HS_BENCH_SPEC_MAX];
    snprintf(label, sizeof(label), "%s",
             !product && s->renderer.method == XRSC_METHOD_SAMPLECACHE ? "sc" : method);
    char name[HS_BENCH_SPEC_MAX] = "";
    char *save = NULL;
    bool first = true, shade_given = false, rate_given = false;
    hs_replay_given rules = {0};
    for (char *kv = args ? strtok_r(args, ",", &save) : NULL; kv;
         kv = strtok_r(NULL, ",", &save)) {
        trim(&kv);
        if (!kv[0])
            continue;
        char *eq = strchr(kv, '=');
        if (!eq)
            return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "--settings",
                              "'%s': expected KEY=VALUE", kv);
        *eq = '\0';
        char *key = kv, *val = eq + 1;
        trim(&key);
        trim(&val);
        if (!strcmp(key, "name")) {
            snprintf(name, sizeof(name), "%s", val);
            continue;
        }
        const bench_key *bk = NULL;
        for (size_t k = 0; k < KEY_COUNT; k++)
            if (!strcmp(keys[k].key, key))
                bk = &keys[k];
        if (!bk)
            return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "--settings",
                              "unknown key '%s' (xrsc bench --help lists them)", key);
        if (!(bk->methods & (1u << s->renderer.method)))
            return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "--settings",
                              "key '%s' does not apply to method %s", key, method);
        shade_given |= !strcmp(key, "shade");
        rate_given |= !strcmp(key, "shade_rate");
        rules.taa_motion |= !strcmp(key, "taa_motion");
        rules.blend_instances |= !strcmp(key, "blend_inst");
        rules.moving |= !strcmp(key, "moving");
        rules.cover |= !strcmp(key, "cover");
        const char *why = bk->set(&s->renderer, val);
        if (why)
            return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "--settings",
                              "%s=%s: expected %s", key, val, why);
        char item[HS_BENCH_SPEC_MAX];
        snprintf(item, sizeof(item), "%s=%s", key, val);
        append(s->spec, sizeof(s->spec), first ? ":" : ",", item);
        if (!strcmp(key, "r")) {
            s->r = strtod(val, NULL);
        } else {
            bool gfirst = strchr(s->group, ':') == NULL;
            append(s->group, sizeof(s->group), gfirst ? ":" : ",", item);
        }
        first = false;
        if (!bk->short_name)
            append(label, sizeof(label), "-", item);
        else {
            snprintf(item, sizeof(item), "%s%s", bk->short_name, val);
            append(label, sizeof(label), "-", item);
        }
    }
    if (product) { /* a shading mode given without a rate: the library's rate, as in the replay */
        hs_replay_default_shading(&s->renderer, shade_given, rate_given);
        hs_replay_default_rules(&s->renderer, rules);
    }
    const char *final = name[0] ? name : label;
    if (!valid_name(final))
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "--settings",
                          "label '%s': use 1..%d of letters, digits and . _ + - (name=LABEL)",
                          final, HS_BENCH_NAME_MAX - 1);
    snprintf(s->name, sizeof(s->name), "%s", final);
    return XRSC_OK;
}

xrsc_result hs_bench_parse_settings(const char *text, hs_bench_setting *out, uint32_t max_count,
                                    uint32_t *out_count, xrsc_diag *diag)
{
    *out_count = 0;
    if (!text)
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "--settings", "no settings");
    char *copy = strdup(text);
    if (!copy)
        return u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, "", 0, "--settings", "copy");
    xrsc_result res = XRSC_OK;
    uint32_t n = 0;
    char *save = NULL;
    /* ';' and newlines separate settings; '#' starts a comment (settings files). */
    for (char *p = copy; *p; p++)
        if (*p == '#')
            while (*p && *p != '\n')
                *p++ = ' ';
    for (char *one = strtok_r(copy, ";\n", &save); one; one = strtok_r(NULL, ";\n", &save)) {
        char *t = one;
        trim(&t);
        if (!t[0])
            continue;
        if (n == max_count) {
            res = u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "--settings",
                             "more than %u settings", max_count);
            break;
        }
        if ((res = parse_one(t, &out[n], diag)) != XRSC_OK)
            break;
        for (uint32_t k = 0; k < n; k++)
            if (!strcmp(out[k].name, out[n].name)) {
                res = u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "--settings",
                                 "two settings are labelled '%s' (give one name=LABEL)",
                                 out[n].name);
                break;
            }
        if (res != XRSC_OK)
            break;
        n++;
    }
    free(copy);
    if (res == XRSC_OK && n == 0)
        res = u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "--settings", "no settings");
    *out_count = res == XRSC_OK ? n : 0;
    return res;
}
