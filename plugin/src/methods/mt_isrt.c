// SPDX-License-Identifier: MIT
/**
 * @file mt_isrt.c
 * @brief Method `isrt`: the sample cache with the superresolution layout of interactive stable
 *        ray tracing [DSK*17], as seed 000 §5 (Fig. 10) compares against it.
 *
 * Slot s of a pixel is the fixed sub-pixel cell (s % M, s / M) of an M x M grid instead of a
 * free position: forward reprojection puts a sample into the cell that contains its new
 * position (the closest one wins a contested cell), every cell without a visible sample is
 * traced through its centre, and the shading cache and reconstruction are the sample cache's
 * own (the branches on xs_sc_params.isrt_m in the sc_* shaders).
 */
#include "mt_samplecache.h"

#include "u_diag.h"

/* M when the option is 0 (seed 000 Fig. 10 uses M = 2 and 3). */
#define MT_ISRT_DEFAULT_M 2u

_Static_assert((XS_SC_ISRT_MAX_M) * (XS_SC_ISRT_MAX_M) <= XS_SC_MAX_SLOTS,
               "M x M cells: mask bits");

xrsc_result mt_isrt_create(const mt_env *env, const xrsc_isrt_options *isrt,
                           const xrsc_samplecache_options *options, mt_method **out,
                           xrsc_diag *diag)
{
    *out = NULL;
    uint32_t m = isrt && isrt->m ? isrt->m : MT_ISRT_DEFAULT_M;
    if (m > XS_SC_ISRT_MAX_M)
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "isrt.m", "M = %u, not 1..%u",
                          m, XS_SC_ISRT_MAX_M);
    mt_sc_variant variant = {.name = "isrt", .isrt_m = m};
    return mt_samplecache_create_variant(env, options, &variant, out, diag);
}
