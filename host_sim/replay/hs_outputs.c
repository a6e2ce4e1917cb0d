// SPDX-License-Identifier: MIT
/**
 * @file hs_outputs.c
 * @brief EXR frames and the ffmpeg side-by-side video of a replay (hs_outputs.h).
 */
#include "hs_outputs.h"

#include "hs_exr.h"
#include "hs_image.h"
#include "u_diag.h"

#include <errno.h>
#include <fcntl.h>
#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

/** Longest path or command line built here. */
#define PATH_CHARS 1200

struct hs_outputs {
    const hs_replay_options *opt;
    uint32_t w, h;
    bool exr;
    float *color[2], *depth; /**< the eyes' colour, one eye's depth */
    hs_autoexposure autoexp; /**< --exposure auto: as the replay's PNGs (hs_image.h) */
    uint8_t *ldr[2], *sbs;
    FILE *video; /**< ffmpeg's stdin; NULL without a video */
    pid_t ffmpeg_pid;
    char video_tmp[PATH_CHARS];
    xrsc_renderer *depth_r; /**< the EXRs' Z when set (hs_outputs_set_depth), else the frame's */
};

/* The ffmpeg program: XRSC_FFMPEG, else "ffmpeg"; found as execvp would (a name with '/' as
 * is, else on PATH). Returns false when there is none. */
static const char *ffmpeg_name(void)
{
    const char *name = getenv("XRSC_FFMPEG");
    return name && *name ? name : "ffmpeg";
}

static bool find_ffmpeg(char *out, size_t cap)
{
    const char *name = ffmpeg_name();
    if (strchr(name, '/')) {
        snprintf(out, cap, "%s", name);
        return access(out, X_OK) == 0;
    }
    const char *path = getenv("PATH");
    for (const char *p = path ? path : ""; *p;) {
        const char *colon = strchr(p, ':');
        size_t len = colon ? (size_t)(colon - p) : strlen(p);
        snprintf(out, cap, "%.*s/%s", (int)len, len ? p : ".", name);
        if (access(out, X_OK) == 0)
            return true;
        p = colon ? colon + 1 : p + len;
    }
    return false;
}

/* FILE.ext -> FILE.partial.ext (ffmpeg chooses the container by the extension). */
static void partial_name(const char *path, char *out, size_t cap)
{
    const char *slash = strrchr(path, '/'), *dot = strrchr(path, '.');
    if (!dot || (slash && dot < slash))
        snprintf(out, cap, "%s.partial", path);
    else
        snprintf(out, cap, "%.*s.partial%s", (int)(dot - path), path, dot);
}

/* Starts ffmpeg (path) with args on a pipe that becomes its stdin, in a process group of its
 * own: a Ctrl-C at the terminal reaches only xrsc, which finishes its frame and then closes the
 * pipe, so ffmpeg ends the video properly instead of stopping with the signal. */
static bool spawn_ffmpeg(hs_outputs *o, const char *path, char *const argv[])
{
    int fds[2];
    if (pipe(fds) != 0)
        return false;
    fcntl(fds[1], F_SETFD, FD_CLOEXEC); /* the child keeps only the read end */
    pid_t pid = fork();
    if (pid == 0) {
        setpgid(0, 0);
        if (dup2(fds[0], STDIN_FILENO) < 0)
            _exit(127);
        close(fds[0]);
        execv(path, argv);
        _exit(127);
    }
    close(fds[0]);
    o->video = pid > 0 ? fdopen(fds[1], "w") : NULL;
    if (!o->video) {
        close(fds[1]);
        if (pid > 0)
            waitpid(pid, NULL, 0);
        return false;
    }
    o->ffmpeg_pid = pid;
    return true;
}

static xrsc_result open_video(hs_outputs *o, double fps, xrsc_diag *diag)
{
    const char *path = o->opt->video_path;
    char ffmpeg[PATH_CHARS], size[48], rate[32];
    if (!find_ffmpeg(ffmpeg, sizeof(ffmpeg))) {
        const char *name = ffmpeg_name();
        U_LOG_W("--video %s: ffmpeg is not installed (no executable '%s'%s); the run goes on "
                "without a video (install ffmpeg, e.g. apt-get install ffmpeg)",
                path, name, strchr(name, '/') ? "" : " on PATH");
        return XRSC_OK;
    }
    partial_name(path, o->video_tmp, sizeof(o->video_tmp));
    snprintf(size, sizeof(size), "%ux%u", 2 * o->w, o->h);
    snprintf(rate, sizeof(rate), "%.6g", fps);
    /* Raw RGB24 frames in; yuv420p out (what players expect), which needs even sides: pad by
     * one pixel where odd. The codec is ffmpeg's default for the file's extension. */
    char *const argv[] = {ffmpeg,
                          "-hide_banner",
                          "-loglevel",
                          "error",
                          "-y",
                          "-f",
                          "rawvideo",
                          "-pix_fmt",
                          "rgb24",
                          "-s",
                          size,
                          "-framerate",
                          rate,
                          "-i",
                          "-",
                          "-vf",
                          "pad=ceil(iw/2)*2:ceil(ih/2)*2",
                          "-pix_fmt",
                          "yuv420p",
                          o->video_tmp,
                          NULL};
    if (!spawn_ffmpeg(o, ffmpeg, argv))
        return u_diag_set(diag, XRSC_ERROR_IO, path, 0, "--video", "cannot start %s: %s", ffmpeg,
                          strerror(errno));
    return XRSC_OK;
}

xrsc_result hs_outputs_open(const hs_replay_options *opt, uint32_t w, uint32_t h, double fps,
                            hs_outputs **out, xrsc_diag *diag)
{
    *out = NULL;
    bool exr = opt->write_exr && opt->out_dir;
    if (!exr && !(opt->video_path && *opt->video_path))
        return XRSC_OK;
    hs_outputs *o = calloc(1, sizeof(*o));
    size_t n = (size_t)w * h;
    if (o) {
        o->opt = opt;
        o->w = w;
        o->h = h;
        o->exr = exr;
        o->color[0] = malloc(n * 4 * sizeof(float));
        o->color[1] = malloc(n * 4 * sizeof(float));
        o->depth = malloc(n * sizeof(float));
        o->ldr[0] = malloc(n * 3);
        o->ldr[1] = malloc(n * 3);
        o->sbs = malloc(n * 6);
    }
    if (!o || !o->color[0] || !o->color[1] || !o->depth || !o->ldr[0] || !o->ldr[1] || !o->sbs) {
        hs_outputs_close(&o, false, NULL);
        return u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, "", 0, "", "output buffers");
    }
    xrsc_result res = opt->video_path && *opt->video_path ? open_video(o, fps, diag) : XRSC_OK;
    if (res != XRSC_OK || (!o->exr && !o->video)) {
        hs_outputs_close(&o, false, NULL);
        return res;
    }
    *out = o;
    return XRSC_OK;
}

/* Writes the frame into ffmpeg's pipe. SIGPIPE (ffmpeg gone) is held back in this thread and
 * discarded, so a dead ffmpeg is an error here rather than the end of the process. */
static xrsc_result write_video(hs_outputs *o, xrsc_diag *diag)
{
    sigset_t pipe_set, old;
    sigemptyset(&pipe_set);
    sigaddset(&pipe_set, SIGPIPE);
    pthread_sigmask(SIG_BLOCK, &pipe_set, &old);
    size_t bytes = (size_t)o->w * 2 * o->h * 3;
    bool ok = fwrite(o->sbs, 1, bytes, o->video) == bytes && fflush(o->video) == 0;
    sigset_t pending;
    if (sigpending(&pending) == 0 && sigismember(&pending, SIGPIPE)) {
        const struct timespec zero = {0, 0};
        sigtimedwait(&pipe_set, NULL, &zero);
    }
    pthread_sigmask(SIG_SETMASK, &old, NULL);
    if (!ok)
        return u_diag_set(diag, XRSC_ERROR_IO, o->opt->video_path, 0, "--video",
                          "ffmpeg stopped reading frames (its error is above)");
    return XRSC_OK;
}

/* The EXR files of both eyes, staged into set (hs_file.h). */
static xrsc_result stage_exrs(hs_outputs *o, xrsc_renderer *r, uint32_t frame, hs_frame_set *set,
                              xrsc_diag *diag)
{
    static const char *const eye_name[2] = {"left", "right"};
    size_t n = (size_t)o->w * o->h;
    for (uint32_t e = 0; e < 2; e++) {
        xrsc_result res =
            xrsc_renderer_read(r, e, XRSC_OUTPUT_COLOR, o->color[e], n * 4 * sizeof(float));
        if (res == XRSC_OK && o->exr)
            res = xrsc_renderer_read(o->depth_r ? o->depth_r : r, e, XRSC_OUTPUT_DEPTH, o->depth,
                                     n * sizeof(float));
        if (res != XRSC_OK)
            return u_diag_set(diag, res, "", 0, "output", "reading eye %u failed", e);
        if (!o->exr)
            continue;
        char path[PATH_CHARS];
        snprintf(path, sizeof(path), "%s/frame_%05u_%s.exr", o->opt->out_dir, frame, eye_name[e]);
        if ((res = hs_frame_set_add(set, path, diag)) != XRSC_OK ||
            (res = hs_stage_exr(path, o->color[e], o->depth, o->w, o->h, diag)) != XRSC_OK)
            return res;
    }
    return XRSC_OK;
}

xrsc_result hs_outputs_frame(hs_outputs *o, xrsc_renderer *r, uint32_t frame, hs_frame_set *set,
                             xrsc_diag *diag)
{
    if (!o)
        return XRSC_OK;
    hs_frame_set own = {0};
    xrsc_result res = stage_exrs(o, r, frame, set ? set : &own, diag);
    if (res != XRSC_OK) {
        hs_frame_set_abort(set ? set : &own);
        return res;
    }
    if (!set && (res = hs_frame_set_commit(&own, diag)) != XRSC_OK)
        return res;
    if (!o->video)
        return XRSC_OK;
    /* One exposure for both eyes, fixed or automatic, as the side-by-side PNG's. */
    const float *eyes[2] = {o->color[0], o->color[1]};
    hs_tonemap tm = {.exposure = o->opt->exposure > 0.0f
                                     ? o->opt->exposure
                                     : hs_autoexposure_update(&o->autoexp, eyes, 2, o->w, o->h)};
    for (int e = 0; e < 2; e++)
        hs_tonemap_rgba(&tm, o->color[e], o->w, o->h, o->ldr[e]);
    hs_side_by_side(o->ldr[0], o->ldr[1], o->w, o->h, o->sbs);
    return write_video(o, diag);
}

void hs_outputs_set_depth(hs_outputs *o, xrsc_renderer *depth)
{
    if (o)
        o->depth_r = depth;
}

xrsc_result hs_outputs_close(hs_outputs **po, bool keep, xrsc_diag *diag)
{
    hs_outputs *o = po ? *po : NULL;
    if (!o)
        return XRSC_OK;
    *po = NULL;
    xrsc_result res = XRSC_OK;
    if (o->video) {
        sigset_t pipe_set, old;
        sigemptyset(&pipe_set);
        sigaddset(&pipe_set, SIGPIPE);
        pthread_sigmask(SIG_BLOCK, &pipe_set, &old);
        fclose(o->video); /* end of input: ffmpeg finishes the file */
        pthread_sigmask(SIG_SETMASK, &old, NULL);
        int status = -1;
        while (waitpid(o->ffmpeg_pid, &status, 0) < 0 && errno == EINTR)
            ;
        bool ok = status != -1 && WIFEXITED(status) && WEXITSTATUS(status) == 0;
        if (keep && !ok)
            res = u_diag_set(diag, XRSC_ERROR_IO, o->opt->video_path, 0, "--video",
                             "ffmpeg failed (exit status %d; its error is above)",
                             status != -1 && WIFEXITED(status) ? WEXITSTATUS(status) : -1);
        if (keep && ok && rename(o->video_tmp, o->opt->video_path) != 0)
            res = u_diag_set(diag, XRSC_ERROR_IO, o->opt->video_path, 0, "--video",
                             "cannot rename %s into place: %s", o->video_tmp, strerror(errno));
        if (!keep || res != XRSC_OK)
            remove(o->video_tmp);
    }
    free(o->color[0]);
    free(o->color[1]);
    free(o->depth);
    free(o->ldr[0]);
    free(o->ldr[1]);
    free(o->sbs);
    free(o);
    return res;
}
