// SPDX-License-Identifier: MIT
/**
 * @file hs_preview_link.c
 * @brief The pipe that tells the runtime's preview window the run's settings and per-frame
 *        timings (hs_preview_link.h).
 */
#define _GNU_SOURCE /* pipe2 */
#include "hs_preview_link.h"

#include "u_diag.h"

#include <errno.h>
#include <fcntl.h>
#include <pthread.h>
#include <time.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/** One line of the channel at most (the runtime drops longer ones). */
#define LINK_LINE_MAX 1024
/** How often the watcher looks at the run's stop flag (Ctrl-C), ns. */
#define LINK_STOP_POLL_NS 50000000L

struct hs_preview_link {
    int fd[2];                         /**< read end (the runtime's), write end (ours) */
    const volatile sig_atomic_t *stop; /**< the run's Ctrl-C flag (hs_replay_options.stop) */
    pthread_t watcher;
    bool watching;
    pthread_mutex_t lock;
    bool quit; /**< under lock: the watcher ends */
};

static bool env_on(const char *name)
{
    const char *v = getenv(name);
    return v && (!strcmp(v, "1") || !strcmp(v, "on"));
}

static void send_line(hs_preview_link *link, const char *line)
{
    size_t n = strlen(line);
    /* Writes of up to PIPE_BUF bytes are atomic: a line arrives whole or not at all. */
    if (write(link->fd[1], line, n) < 0 && errno != EAGAIN)
        U_LOG_D("preview link: write failed: %s", strerror(errno));
}

/* A word for the line: spaces and '=' would break its syntax. */
static void word(const char *in, char *out, size_t size)
{
    size_t i = 0;
    for (; in && in[i] && i + 1 < size; i++)
        out[i] = (in[i] == ' ' || in[i] == '=' || in[i] == '\n') ? '_' : in[i];
    out[i] = '\0';
}

/* Ctrl-C while the window holds the frame loop paused (inside xrWaitFrame) would never reach
 * the loop that checks the flag: this thread watches it and tells the window to let go
 * ("stop": resume and close at the end). A thread, because a signal handler must not call
 * into the runtime. */
static void *watch_stop(void *arg)
{
    hs_preview_link *link = arg;
    for (;;) {
        pthread_mutex_lock(&link->lock);
        bool quit = link->quit;
        pthread_mutex_unlock(&link->lock);
        if (quit)
            return NULL;
        if (*link->stop) {
            send_line(link, "stop\n");
            return NULL;
        }
        struct timespec ts = {0, LINK_STOP_POLL_NS};
        nanosleep(&ts, NULL);
    }
}

xrsc_result hs_preview_link_open(const hs_replay_options *opt, hs_preview_link **out,
                                 xrsc_diag *diag)
{
    *out = NULL;
    if (!opt->preview && !env_on("XRSC_RT_PREVIEW"))
        return XRSC_OK;
    hs_preview_link *link = calloc(1, sizeof(*link));
    if (!link)
        return u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, "", 0, "--preview", "out of memory");
    pthread_mutex_init(&link->lock, NULL);
    if (pipe2(link->fd, O_CLOEXEC | O_NONBLOCK) != 0) {
        pthread_mutex_destroy(&link->lock);
        free(link);
        return u_diag_set(diag, XRSC_ERROR_IO, "", 0, "--preview", "pipe: %s", strerror(errno));
    }
    char buf[64];
    snprintf(buf, sizeof(buf), "%d", link->fd[0]);
    if (setenv("XRSC_RT_PREVIEW", "1", 1) || setenv("XRSC_RT_PREVIEW_INFO_FD", buf, 1) ||
        (opt->preview_autoclose && setenv("XRSC_RT_PREVIEW_AUTOCLOSE", "1", 1)) ||
        (opt->preview_reference &&
         setenv("XRSC_RT_PREVIEW_REFERENCE", opt->preview_reference, 1))) {
        hs_preview_link_close(&link);
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, "", 0, "--preview", "setenv: %s",
                          strerror(errno));
    }
    char method[64], blend[64], line[LINK_LINE_MAX];
    word(xrsc_method_name(opt->renderer.method), method, sizeof(method));
    word(xrsc_blend_name(opt->renderer.blend), blend, sizeof(blend));
    snprintf(line, sizeof(line), "run method=%s blend=%s r=%g\n", method, blend,
             (double)opt->renderer.blend_r);
    send_line(link, line);
    link->stop = opt->stop;
    link->watching = link->stop && pthread_create(&link->watcher, NULL, watch_stop, link) == 0;
    *out = link;
    return XRSC_OK;
}

void hs_preview_link_frame(hs_preview_link *link, uint64_t frame, double render_ms,
                           const xrsc_pass_timing *passes, uint32_t pass_count)
{
    if (!link)
        return;
    char line[LINK_LINE_MAX], name[64];
    int n =
        snprintf(line, sizeof(line), "frame %llu ms=%.3f", (unsigned long long)frame, render_ms);
    for (uint32_t p = 0; p < pass_count && n > 0 && (size_t)n < sizeof(line) - 80; p++) {
        word(passes[p].name, name, sizeof(name));
        n += snprintf(line + n, sizeof(line) - (size_t)n, " %s=%.3f", name, passes[p].gpu_ms);
    }
    if (n > 0 && (size_t)n < sizeof(line) - 1) {
        line[n] = '\n';
        line[n + 1] = '\0';
        send_line(link, line);
    }
}

void hs_preview_link_autoclose(hs_preview_link *link)
{
    if (link)
        send_line(link, "autoclose\n");
}

void hs_preview_link_close(hs_preview_link **pl)
{
    if (!pl || !*pl)
        return;
    hs_preview_link *link = *pl;
    *pl = NULL;
    if (link->watching) {
        pthread_mutex_lock(&link->lock);
        link->quit = true;
        pthread_mutex_unlock(&link->lock);
        pthread_join(link->watcher, NULL);
    }
    pthread_mutex_destroy(&link->lock);
    close(link->fd[0]);
    close(link->fd[1]);
    unsetenv("XRSC_RT_PREVIEW_INFO_FD");
    free(link);
}
