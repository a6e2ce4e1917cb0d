// SPDX-License-Identifier: MIT
/**
 * @file t_render.h
 * @brief The GPU tests' steps through the public API: a scene loaded, and frames rendered by
 *        a renderer made for them, their colour read back (every step checked).
 */
#pragma once

#include "t_frames.h"
#include "testing.h"
#include "xrsc/xrsc.h"

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

/** The glTF at path loaded into ctx; NULL (a failed check naming the error) when it is not. */
static inline xrsc_scene *t_scene_load(xrsc_context *ctx, const char *path)
{
    xrsc_scene *s = NULL;
    xrsc_diag d = {0};
    char buf[1400];
    xrsc_result r = xrsc_scene_load(ctx, path, NULL, &s, &d);
    CHECK_MSG(r == XRSC_OK, "load %s: %s", path, xrsc_diag_format(&d, buf, sizeof buf));
    return s;
}

/** What t_render draws and reads. Zero-initialised: one frame, both eyes, no timings. */
typedef struct t_render_job {
    uint32_t frames;           /**< frames of the view, frame_index 0, 1, ... (0: 1) */
    uint64_t time_step_ns;     /**< added to display_time_ns before each frame (0: still) */
    uint32_t eyes;             /**< eyes read, left first: 1 or 2 (0: 2) */
    xrsc_pass_timing *timings; /**< not NULL: the last frame's passes (XRSC_MAX_PASSES room) */
    uint32_t timing_count;     /**< out: how many timings */
} t_render_job;

/**
 * Makes a renderer with ro (width and height set) on scene, renders job's frames (NULL: one)
 * of the view f and reads job's eyes' colour into out: ro->width x ro->height RGBA floats an
 * eye, left first. Whether every step succeeded (each is a check).
 */
static inline bool t_render(xrsc_context *ctx, xrsc_scene *scene, const xrsc_renderer_options *ro,
                            const xrsc_frame *f, t_render_job *job, float *out)
{
    t_render_job one = {0};
    job = job ? job : &one;
    xrsc_renderer *r = NULL;
    xrsc_diag d = {0};
    char buf[1400];
    xrsc_result res = xrsc_renderer_create(ctx, scene, ro, &r, &d);
    CHECK_MSG(res == XRSC_OK, "renderer: %s", xrsc_diag_format(&d, buf, sizeof buf));
    if (res != XRSC_OK)
        return false;
    xrsc_frame frame = *f;
    for (uint32_t i = 0; i < (job->frames ? job->frames : 1) && res == XRSC_OK; i++) {
        frame.display_time_ns += job->time_step_ns;
        frame.frame_index = i;
        res = xrsc_renderer_render(r, &frame);
    }
    CHECK_EQ_INT(res, XRSC_OK);
    size_t layer = (size_t)ro->width * ro->height * 4;
    for (uint32_t e = 0; e < (job->eyes ? job->eyes : 2) && res == XRSC_OK; e++)
        res = xrsc_renderer_read(r, e, XRSC_OUTPUT_COLOR, out + e * layer, layer * sizeof(float));
    CHECK_EQ_INT(res, XRSC_OK);
    if (job->timings)
        job->timing_count = xrsc_renderer_timings(r, job->timings, XRSC_MAX_PASSES);
    xrsc_renderer_destroy(&r);
    return res == XRSC_OK;
}

/** As t_render, into a new array (free it) of job's eyes; NULL when a step failed. */
static inline float *t_render_image(xrsc_context *ctx, xrsc_scene *scene,
                                    const xrsc_renderer_options *ro, const xrsc_frame *f,
                                    t_render_job *job)
{
    uint32_t eyes = job && job->eyes ? job->eyes : 2;
    float *px = malloc((size_t)eyes * ro->width * ro->height * 4 * sizeof(float));
    CHECK(px != NULL);
    if (px && !t_render(ctx, scene, ro, f, job, px)) {
        free(px);
        return NULL;
    }
    return px;
}

/** Loads the glTF at path, renders it as t_render_image does from the view f (NULL: the
 *  identity view, t_frame_identity) and frees the scene; the image or NULL. */
static inline float *t_render_file(xrsc_context *ctx, const char *path,
                                   const xrsc_renderer_options *ro, const xrsc_frame *f,
                                   t_render_job *job)
{
    xrsc_frame identity;
    t_frame_identity(&identity);
    xrsc_scene *scene = t_scene_load(ctx, path);
    float *px = scene ? t_render_image(ctx, scene, ro, f ? f : &identity, job) : NULL;
    xrsc_scene_destroy(&scene);
    return px;
}
