// SPDX-License-Identifier: MIT
/**
 * @file mt_taa.c
 * @brief Method `taa`'s rendering ([YLS20] as seed 000 §5 uses it): one path-traced sample per
 *        pixel (spp.rgen) at a Halton(2,3) sub-pixel position that changes every frame; the
 *        temporal filter is the renderer's TAA post-pass (plugin/src/temporal/).
 *
 * The jitter ([YLS20]): frame f samples every pixel of both eyes at Halton point
 * (f mod XS_TF_HALTON_PERIOD) + 1 of bases 2 and 3. Both eyes share the offset, so jitter
 * adds no stereo difference of its own (the eyes' images sample the same sub-pixel positions),
 * and the sequence is a function of frame_index only, so replays are repeatable.
 */
#include "mt_trace.h"

#include "u_diag.h"
#include "xs_taa.h"

#include <stdlib.h>
#include <string.h>

typedef struct mt_taa {
    mt_method base;
    mt_trace trace;
    gpu_image mu1, mu2; /**< raw moments of the pixel's sample (set 1 of spp.rgen) */
    uint32_t max_bounces;
} mt_taa;

_Static_assert(offsetof(mt_taa, base) == 0, "base first");

static xrsc_result taa_render(mt_method *m, const xrsc_frame *frame, xrsc_diag *diag)
{
    mt_taa *s = (mt_taa *)m;
    xs_frame xf;
    mt_trace_frame_constants(&s->trace, frame, &xf);
    xf.samples_per_pixel = 1;
    xf.max_bounces = s->max_bounces;
    uint32_t index = frame->frame_index % XS_TF_HALTON_PERIOD + 1u;
    xf.jitter = XS_JITTER_OFFSET;
    xf.jitter_x = xs_tf_halton(index, 2u);
    xf.jitter_y = xs_tf_halton(index, 3u);
    return mt_trace_run(&s->trace, &xf, false, diag);
}

static const gpu_image *moment_image(const mt_taa *s, xrsc_output output)
{
    return output == XRSC_OUTPUT_MU1 ? &s->mu1 : output == XRSC_OUTPUT_MU2 ? &s->mu2 : NULL;
}

static size_t taa_output_size(const mt_method *m, xrsc_output output)
{
    const gpu_image *mu = moment_image((const mt_taa *)m, output);
    if (mu)
        return (size_t)mu->width * mu->height * mu->texel_size;
    return mt_trace_output_size(&((const mt_taa *)m)->trace, output);
}

static xrsc_result taa_read(mt_method *m, uint32_t eye, xrsc_output output, void *dst,
                            size_t dst_size, xrsc_diag *diag)
{
    mt_taa *s = (mt_taa *)m;
    const gpu_image *mu = moment_image(s, output);
    if (mu) {
        if (eye > 1)
            return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "eye", "eye %u", eye);
        return gpu_image_read_layer(s->trace.env.gpu, mu, eye, dst, dst_size, diag);
    }
    return mt_trace_read(&s->trace, eye, output, dst, dst_size, diag);
}

static uint32_t taa_timings(const mt_method *m, xrsc_pass_timing *out, uint32_t max_count)
{
    return mt_trace_timings(&((const mt_taa *)m)->trace, out, max_count);
}

static uint64_t taa_rays(const mt_method *m)
{
    return ((const mt_taa *)m)->trace.rays;
}

static const gpu_image *taa_output_image(const mt_method *m, xrsc_output output)
{
    const gpu_image *mu = moment_image((const mt_taa *)m, output);
    return mu ? mu : mt_trace_output_image(&((const mt_taa *)m)->trace, output);
}

static void taa_destroy(mt_method *m)
{
    mt_taa *s = (mt_taa *)m;
    if (s->trace.env.gpu) {
        vkDeviceWaitIdle(s->trace.env.gpu->device);
        gpu_image_destroy(s->trace.env.gpu, &s->mu2);
        gpu_image_destroy(s->trace.env.gpu, &s->mu1);
    }
    mt_trace_fini(&s->trace);
    free(s);
}

xrsc_result mt_taa_create(const mt_env *env, const xrsc_spp_options *options, mt_method **out,
                          xrsc_diag *diag)
{
    *out = NULL;
    mt_taa *s = calloc(1, sizeof(*s));
    if (!s)
        return u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, "", 0, "", "out of memory");
    uint32_t bounces = options ? options->max_bounces : 0u;
    s->max_bounces = bounces == 0u                  ? XS_DEFAULT_MAX_BOUNCES
                     : bounces == XRSC_BOUNCES_NONE ? 0u
                                                    : bounces;
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
    if ((res = gpu_image_create_storage(env->gpu, VK_FORMAT_R32G32B32A32_SFLOAT, env->width,
                                        env->height, 2, &s->mu1, diag)) != XRSC_OK ||
        (res = gpu_image_create_storage(env->gpu, VK_FORMAT_R32G32B32A32_SFLOAT, env->width,
                                        env->height, 2, &s->mu2, diag)) != XRSC_OK) {
        taa_destroy(&s->base);
        return res;
    }
    gpu_descriptors_write_storage_image(env->gpu, &s->trace.program.set1, XS_SPP_BIND_MU1, &s->mu1);
    gpu_descriptors_write_storage_image(env->gpu, &s->trace.program.set1, XS_SPP_BIND_MU2, &s->mu2);
    s->base = (mt_method){
        .name = "taa",
        .render = taa_render,
        .output_size = taa_output_size,
        .read = taa_read,
        .timings = taa_timings,
        .rays_last_frame = taa_rays,
        .destroy = taa_destroy,
        .output_image = taa_output_image,
    };
    *out = &s->base;
    return XRSC_OK;
}
