// SPDX-License-Identifier: MIT
/**
 * @file mt_primary.c
 * @brief Method `primary`: one camera ray per pixel through its centre, first-hit albedo.
 */
#include "mt_trace.h"

#include "u_diag.h"

#include <stdlib.h>

typedef struct mt_primary {
    mt_method base;
    mt_trace trace;
} mt_primary;

_Static_assert(offsetof(mt_primary, base) == 0, "base first");

static xrsc_result primary_render(mt_method *m, const xrsc_frame *frame, xrsc_diag *diag)
{
    mt_primary *p = (mt_primary *)m;
    xs_frame xf;
    mt_trace_frame_constants(&p->trace, frame, &xf);
    xf.samples_per_pixel = 1;
    xf.max_bounces = 0;
    xf.jitter = 0;
    xf.accumulate = 0;
    return mt_trace_run(&p->trace, &xf, false, diag);
}

static size_t primary_output_size(const mt_method *m, xrsc_output output)
{
    return mt_trace_output_size(&((const mt_primary *)m)->trace, output);
}

static xrsc_result primary_read(mt_method *m, uint32_t eye, xrsc_output output, void *dst,
                                size_t dst_size, xrsc_diag *diag)
{
    return mt_trace_read(&((mt_primary *)m)->trace, eye, output, dst, dst_size, diag);
}

static uint32_t primary_timings(const mt_method *m, xrsc_pass_timing *out, uint32_t max_count)
{
    return mt_trace_timings(&((const mt_primary *)m)->trace, out, max_count);
}

static uint64_t primary_rays(const mt_method *m) { return ((const mt_primary *)m)->trace.rays; }

static const gpu_image *primary_output_image(const mt_method *m, xrsc_output output)
{
    return mt_trace_output_image(&((const mt_primary *)m)->trace, output);
}

static void primary_destroy(mt_method *m)
{
    mt_primary *p = (mt_primary *)m;
    mt_trace_fini(&p->trace);
    free(p);
}

xrsc_result mt_primary_create(const mt_env *env, mt_method **out, xrsc_diag *diag)
{
    *out = NULL;
    mt_primary *p = calloc(1, sizeof(*p));
    if (!p)
        return u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, "", 0, "", "out of memory");
    xrsc_result res = mt_trace_init(&p->trace, env, "primary.rgen", diag);
    if (res != XRSC_OK) {
        free(p);
        return res;
    }
    p->base = (mt_method){
        .name = "primary",
        .render = primary_render,
        .output_size = primary_output_size,
        .read = primary_read,
        .timings = primary_timings,
        .rays_last_frame = primary_rays,
        .destroy = primary_destroy,
        .output_image = primary_output_image,
    };
    *out = &p->base;
    return XRSC_OK;
}
