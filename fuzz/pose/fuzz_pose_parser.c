// SPDX-License-Identifier: MIT
/**
 * @file fuzz_pose_parser.c
 * @brief libFuzzer target: hs_pose_stream_parse in every format, then lookups and anchoring.
 */
#include "hs_pose_stream.h"

#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc;
    (void)argv;
    setenv("XRSC_LOG", "quiet", 1); /* the duplicate-timestamp warning would flood stderr */
    return 0;
}

static const hs_pose_format fuzz_formats[] = {HS_POSE_FORMAT_AUTO, HS_POSE_FORMAT_XRSC,
                                              HS_POSE_FORMAT_PRED6DOF, HS_POSE_FORMAT_360VIDEO};

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    for (size_t i = 0; i < sizeof(fuzz_formats) / sizeof(fuzz_formats[0]); i++) {
        hs_pose_stream *s = NULL;
        xrsc_diag diag;
        xrsc_result r =
            hs_pose_stream_parse("fuzz", (const char *)data, size, fuzz_formats[i], &s, &diag);
        if (r != XRSC_OK) {
            if (s != NULL || diag.code != r)
                abort(); /* the contract: NULL out and a matching diag on every error */
            continue;
        }
        if (!s || s->count == 0 || s->samples[0].time_ns != 0)
            abort();
        int64_t end = hs_pose_stream_duration_ns(s);
        XrPosef p;
        int64_t after = end < INT64_MAX ? end + 1 : end; /* a span may reach INT64_MAX */
        const int64_t probes[] = {INT64_MIN, -1,      0,   1,     end / 3,
                                  end / 2,   end - 1, end, after, INT64_MAX};
        for (size_t k = 0; k < sizeof(probes) / sizeof(probes[0]); k++)
            hs_pose_stream_sample(s, probes[k], &p);
        hs_pose_stream_anchor(s, xrsc_pose_identity());
        hs_pose_stream_destroy(&s);
    }
    return 0;
}
