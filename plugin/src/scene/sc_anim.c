// SPDX-License-Identifier: MIT
/**
 * @file sc_anim.c
 * @brief Node animation (glTF 2.0 §3.11: LINEAR, STEP, CUBICSPLINE; T/R/S and morph weights),
 *        the clip that plays,
 *        and world transforms.
 */
#include "sc_scene.h"
#include "sc_xform.h"
#include "u_diag.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/** "0 Survey (3.42 s), 1 Walk (0.71 s)" into buf; "none" when there are no clips. */
static void list_clips(const sc_clip *clips, uint32_t n, char *buf, size_t cap)
{
    size_t at = 0;
    buf[0] = '\0';
    if (n == 0) snprintf(buf, cap, "none");
    for (uint32_t i = 0; i < n && at + 1 < cap; i++) {
        int w = snprintf(buf + at, cap - at, "%s%u %s%s%s (%.2f s)", i ? ", " : "", i,
                         clips[i].name[0] ? "\"" : "", clips[i].name[0] ? clips[i].name : "unnamed",
                         clips[i].name[0] ? "\"" : "", (double)clips[i].duration_s);
        if (w < 0) break;
        at += (size_t)w;
    }
}

xrsc_result sc_clip_resolve(const sc_clip *clips, uint32_t clip_count, const char *animation,
                            const char *file, int32_t *out_playing, xrsc_diag *diag)
{
    const char *a = animation ? animation : "";
    *out_playing = clip_count ? 0 : SC_CLIP_NONE;
    if (!a[0] || !strcmp(a, "first")) return XRSC_OK;
    if (!strcmp(a, "none")) {
        *out_playing = SC_CLIP_NONE;
        return XRSC_OK;
    }
    if (!strcmp(a, "all")) {
        *out_playing = clip_count ? SC_CLIP_ALL : SC_CLIP_NONE;
        return XRSC_OK;
    }
    /* A clip's name wins over its reading as an index ("1" may name a clip). */
    for (uint32_t i = 0; i < clip_count; i++)
        if (!strcmp(clips[i].name, a)) {
            *out_playing = (int32_t)i;
            return XRSC_OK;
        }
    char *end = NULL;
    unsigned long idx = strtoul(a, &end, 10);
    if (a[0] >= '0' && a[0] <= '9' && end && !*end && idx < clip_count) {
        *out_playing = (int32_t)idx;
        return XRSC_OK;
    }
    char list[400];
    list_clips(clips, clip_count, list, sizeof list);
    return u_diag_set(diag, XRSC_ERROR_ANIMATION_UNKNOWN, file ? file : "", 0, "animation",
                      "no clip '%s' (--animation takes a clip's name or index, all or none); "
                      "the file's clips: %s",
                      a, list);
}

/** Index k of the key segment [times[k], times[k+1]] containing t (0 <= k < n-1), n >= 2. */
static uint32_t find_segment(const float *times, uint32_t n, float t)
{
    uint32_t lo = 0, hi = n - 1;
    while (hi - lo > 1) {
        uint32_t mid = lo + (hi - lo) / 2;
        if (times[mid] <= t) lo = mid;
        else hi = mid;
    }
    return lo;
}

/** Value of channel ch at time t into out (ch->components floats). */
static void sample_channel(const sc_anim_channel *ch, float t, float *out)
{
    uint32_t nc = ch->components;
    uint32_t n = ch->key_count;
    bool cubic = ch->interp == SC_INTERP_CUBICSPLINE;
    /* CUBICSPLINE stores (in-tangent, value, out-tangent) per key (glTF §3.11.2). */
    uint32_t per_key = cubic ? 3 * nc : nc, value_at = cubic ? nc : 0;
    const float *v = ch->values;
    if (n == 1 || t <= ch->times[0] || t >= ch->times[n - 1]) {
        uint32_t k = (n == 1 || t <= ch->times[0]) ? 0 : n - 1;
        for (uint32_t i = 0; i < nc; i++) out[i] = v[k * per_key + value_at + i];
    } else {
        uint32_t k = find_segment(ch->times, n, t);
        float t0 = ch->times[k], dt = ch->times[k + 1] - t0;
        float u = dt > 0.0f ? (t - t0) / dt : 0.0f;
        const float *a = v + k * per_key + value_at, *b = v + (k + 1) * per_key + value_at;
        if (ch->interp == SC_INTERP_STEP) {
            for (uint32_t i = 0; i < nc; i++) out[i] = a[i];
        } else if (!cubic) {
            if (ch->path == SC_ANIM_ROTATION) {
                sc_quat_slerp(a, b, u, out);
            } else {
                for (uint32_t i = 0; i < nc; i++) out[i] = a[i] + (b[i] - a[i]) * u;
            }
        } else {
            /* Hermite spline with tangents scaled by the key interval (glTF Appendix C). */
            const float *out_tan = a + nc, *in_tan = b - nc;
            float u2 = u * u, u3 = u2 * u;
            float h00 = 2 * u3 - 3 * u2 + 1, h10 = u3 - 2 * u2 + u;
            float h01 = -2 * u3 + 3 * u2, h11 = u3 - u2;
            for (uint32_t i = 0; i < nc; i++)
                out[i] = h00 * a[i] + h10 * dt * out_tan[i] + h01 * b[i] + h11 * dt * in_tan[i];
        }
    }
    if (ch->path == SC_ANIM_ROTATION) sc_quat_normalize(out);
}

void sc_scene_evaluate(sc_scene *scene, double time_s)
{
    if (!scene) return;
    double t = 0.0;
    if (scene->animation_duration_s > 0.0f) {
        double d = scene->animation_duration_s;
        t = fmod(time_s, d);
        if (t < 0.0) t += d;
        /* Looping: the end of the loop shows the last key, not the first one again. */
        if (t == 0.0 && time_s > 0.0) t = d;
    }
    for (uint32_t c = 0; c < scene->channel_count; c++) {
        const sc_anim_channel *ch = &scene->channels[c];
        sc_node *node = &scene->nodes[ch->node];
        if (ch->path == SC_ANIM_WEIGHTS) {
            sample_channel(ch, (float)t, &scene->node_weights[node->first_weight]);
            continue;
        }
        float *dst = ch->path == SC_ANIM_TRANSLATION ? node->translation
                     : ch->path == SC_ANIM_ROTATION  ? node->rotation
                                                     : node->scale;
        sample_channel(ch, (float)t, dst);
    }
    for (uint32_t i = 0; i < scene->node_count; i++) {
        sc_node *n = &scene->nodes[scene->node_order[i]];
        float local[16];
        if (n->has_matrix) memcpy(local, n->matrix, sizeof local);
        else sc_mat4_from_trs(n->translation, n->rotation, n->scale, local);
        if (n->parent < 0) memcpy(n->world, local, sizeof local);
        else sc_mat4_mul(scene->nodes[n->parent].world, local, n->world);
    }
    for (uint32_t i = 0; i < scene->instance_count; i++) {
        sc_instance *in = &scene->instances[i];
        if (in->has_local) sc_mat4_mul(scene->nodes[in->node].world, in->local, in->world);
        else memcpy(in->world, scene->nodes[in->node].world, sizeof in->world);
    }
    sc_scene_pose(scene);
}
