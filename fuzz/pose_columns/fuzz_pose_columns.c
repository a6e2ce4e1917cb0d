// SPDX-License-Identifier: MIT
/**
 * @file fuzz_pose_columns.c
 * @brief libFuzzer target: the column importer (hs_pose_columns_parse and
 *        hs_pose_stream_parse_columns). The first input byte picks a column list, time unit
 *        and handedness from small tables; the rest is the file.
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
    setenv("XRSC_LOG", "quiet", 1);
    return 0;
}

static const char *const fuzz_specs[] = {
    "t,x,y,z,qx,qy,qz,qw", "t,qw,qx,qy,qz,x,y,z", "_,t,x,y,z,qx,qy,qz,qw",
    "t,qx,qy,qz,qw",       "qw,qx,qy,qz,t",       "x,y,z,t,_,qx,qy,qz,qw",
    "t,x,y,z,qx,qy,qz,qw,_,_", "time,px,py,pz,qx,qy,qz,qw",
};
static const char *const fuzz_units[] = {"s", "ms", "us", "ns", "ticks", NULL, "", "s"};
static const char *const fuzz_hands[] = {"right", "left-unity"};

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1)
        return 0;
    uint8_t sel = data[0];
    hs_pose_columns c;
    xrsc_diag diag;
    if (hs_pose_columns_parse(fuzz_specs[sel & 7], fuzz_units[(sel >> 3) & 7],
                              fuzz_hands[(sel >> 6) & 1], &c, &diag) != XRSC_OK)
        abort(); /* every table entry is valid */
    hs_pose_stream *s = NULL;
    xrsc_result r =
        hs_pose_stream_parse_columns("fuzz", (const char *)data + 1, size - 1, &c, &s, &diag);
    if (r != XRSC_OK) {
        if (s != NULL || diag.code != r)
            abort(); /* the contract: NULL out and a matching diag on every error */
        return 0;
    }
    if (!s || s->count == 0 || s->samples[0].time_ns != 0)
        abort();
    for (size_t i = 1; i < s->count; i++)
        if (s->samples[i].time_ns <= s->samples[i - 1].time_ns)
            abort();
    XrPosef p;
    hs_pose_stream_sample(s, hs_pose_stream_duration_ns(s) / 2, &p);
    hs_pose_stream_destroy(&s);
    return 0;
}
