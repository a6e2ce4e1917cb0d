// SPDX-License-Identifier: MIT
/**
 * @file mt_taa.c
 * @brief Method `taa`'s rendering ([YLS20] as seed 000 §5 uses it): one path-traced sample per
 *        pixel (spp.rgen) at a Halton(2,3) sub-pixel position that changes every frame; the
 *        temporal filter is the renderer's TAA post-pass (plugin/src/temporal/).
 *
 * `taa` is `spp` (mt_spp.c: outputs, moments mu1/mu2, frame) at 1 sample per pixel without
 * accumulation, with this file's jitter ([YLS20]): frame f samples every pixel of both eyes at
 * Halton point (f mod XS_TF_HALTON_PERIOD) + 1 of bases 2 and 3. Both eyes share the offset, so
 * jitter adds no stereo difference of its own (the eyes' images sample the same sub-pixel
 * positions), and the sequence is a function of frame_index only, so replays are repeatable.
 */
#include "mt_trace.h"

#include "xs_taa.h"

/** The frame's Halton(2,3) sub-pixel offset, shared by both eyes (mt_spp_jitter_fn). */
static void taa_jitter(const xrsc_frame *frame, xs_frame *xf)
{
    uint32_t index = frame->frame_index % XS_TF_HALTON_PERIOD + 1u;
    xf->jitter = XS_JITTER_OFFSET;
    xf->jitter_x = xs_tf_halton(index, 2u);
    xf->jitter_y = xs_tf_halton(index, 3u);
}

xrsc_result mt_taa_create(const mt_env *env, const xrsc_spp_options *options, mt_method **out,
                          xrsc_diag *diag)
{
    /* only max_bounces is taken from options (mt_method.h); 0 = the default as in `spp` */
    xrsc_spp_options o = {.samples_per_pixel = 1,
                          .max_bounces = options ? options->max_bounces : 0};
    return mt_spp_create_variant(env, &o, "taa", taa_jitter, out, diag);
}
