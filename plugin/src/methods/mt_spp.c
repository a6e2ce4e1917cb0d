// SPDX-License-Identifier: MIT
/**
 * @file mt_spp.c
 * @brief Method `spp`: N path-traced samples per pixel per frame (seed 000 §5.1), with
 *        optional progressive accumulation while the views and the scene time stay the same.
 */
#include "mt_trace.h"

#include "u_diag.h"

#include <stdlib.h>
#include <string.h>

typedef struct mt_spp {
    mt_method base;
    mt_trace trace;
    xrsc_spp_options opt; /**< with defaults filled in */
    bool have_last;
    xrsc_view last_views[2];
    int64_t last_time_ns;
    uint32_t accumulated;    /**< frames summed into the accumulation image */
    mt_spp_jitter_fn jitter; /**< NULL: spp's own (opt.no_jitter); else a variant's */
} mt_spp;

_Static_assert(offsetof(mt_spp, base) == 0, "base first");

static bool same_views(const mt_spp *s, const xrsc_frame *frame)
{
    return s->have_last && s->last_time_ns == frame->display_time_ns &&
           memcmp(s->last_views, frame->views, sizeof(s->last_views)) == 0;
}

static xrsc_result spp_render(mt_method *m, const xrsc_frame *frame, xrsc_diag *diag)
{
    mt_spp *s = (mt_spp *)m;
    xs_frame xf;
    mt_trace_frame_constants(&s->trace, frame, &xf);
    xf.samples_per_pixel = s->opt.samples_per_pixel;
    xf.max_bounces = s->opt.max_bounces == XRSC_BOUNCES_NONE ? 0u : s->opt.max_bounces;
    xf.jitter = s->opt.no_jitter ? 0u : 1u;
    if (s->jitter)
        s->jitter(frame, &xf);
    bool clear = false;
    if (s->opt.accumulate) {
        if (!same_views(s, frame)) {
            clear = true;
            s->accumulated = 0;
        }
        /* frame_index selects the random stream (xrsc.h): callers vary it per frame, or the
         * same samples are summed again. */
        xf.accumulate = 1;
    }
    xrsc_result res = mt_trace_run(&s->trace, &xf, clear, diag);
    if (res != XRSC_OK) {
        s->have_last = false;
        return res;
    }
    s->accumulated++;
    s->have_last = true;
    memcpy(s->last_views, frame->views, sizeof(s->last_views));
    s->last_time_ns = frame->display_time_ns;
    return XRSC_OK;
}

static size_t spp_output_size(const mt_method *m, xrsc_output output)
{
    return mt_trace_output_size(&((const mt_spp *)m)->trace, output);
}

static xrsc_result spp_read(mt_method *m, uint32_t eye, xrsc_output output, void *dst,
                            size_t dst_size, xrsc_diag *diag)
{
    return mt_trace_read(&((mt_spp *)m)->trace, eye, output, dst, dst_size, diag);
}

static uint32_t spp_timings(const mt_method *m, xrsc_pass_timing *out, uint32_t max_count)
{
    return mt_trace_timings(&((const mt_spp *)m)->trace, out, max_count);
}

static uint64_t spp_rays(const mt_method *m) { return ((const mt_spp *)m)->trace.rays; }

static const gpu_image *spp_output_image(const mt_method *m, xrsc_output output)
{
    return mt_trace_output_image(&((const mt_spp *)m)->trace, output);
}

static void spp_destroy(mt_method *m)
{
    mt_spp *s = (mt_spp *)m;
    mt_trace_fini(&s->trace); /* with the moments */
    free(s);
}

xrsc_result mt_spp_create(const mt_env *env, const xrsc_spp_options *options, mt_method **out,
                          xrsc_diag *diag)
{
    return mt_spp_create_variant(env, options, "spp", NULL, out, diag);
}

xrsc_result mt_spp_create_variant(const mt_env *env, const xrsc_spp_options *options,
                                  const char *name, mt_spp_jitter_fn jitter, mt_method **out,
                                  xrsc_diag *diag)
{
    *out = NULL;
    mt_spp *s = calloc(1, sizeof(*s));
    if (!s)
        return u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, "", 0, "", "out of memory");
    if (options)
        s->opt = *options;
    s->jitter = jitter;
    if (s->opt.samples_per_pixel == 0)
        s->opt.samples_per_pixel = 1;
    if (s->opt.max_bounces == 0)
        s->opt.max_bounces = XS_DEFAULT_MAX_BOUNCES;
    static const gpu_binding moment_bindings[] = {
        {XS_SPP_BIND_MU1, GPU_BINDING_STORAGE_IMAGE, 1},
        {XS_SPP_BIND_MU2, GPU_BINDING_STORAGE_IMAGE, 1},
    };
    gpu_rt_program_desc desc = {.raygen = "spp.rgen", .set1 = moment_bindings, .set1_count = 2};
    xrsc_result res = mt_trace_init_program(&s->trace, env, &desc, diag);
    if (res != XRSC_OK) {
        free(s);
        return res;
    }
    if ((res = mt_trace_create_moments(&s->trace, diag)) != XRSC_OK) {
        spp_destroy(&s->base);
        return res;
    }
    gpu_descriptors *set1 = &s->trace.program.set1;
    gpu_descriptors_write_storage_image(env->gpu, set1, XS_SPP_BIND_MU1, &s->trace.mu1);
    gpu_descriptors_write_storage_image(env->gpu, set1, XS_SPP_BIND_MU2, &s->trace.mu2);
    s->base = (mt_method){
        .name = name,
        .render = spp_render,
        .output_size = spp_output_size,
        .read = spp_read,
        .timings = spp_timings,
        .rays_last_frame = spp_rays,
        .destroy = spp_destroy,
        .output_image = spp_output_image,
    };
    *out = &s->base;
    return XRSC_OK;
}
