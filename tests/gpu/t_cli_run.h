// SPDX-License-Identifier: MIT
/**
 * @file t_cli_run.h
 * @brief Helpers of the tests that run the xrsc program as a child (test_cli_ctrlc,
 *        test_cli_ending): start it, poll its folder, and check that every file it left is
 *        whole (frames as complete sets of 32 x 32 eyes, no temporary file).
 */
#pragma once

#include "hs_image.h"
#include "testing.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <png.h>
#include <signal.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#ifndef XRSC_EXE
#error "XRSC_EXE: the path of the built xrsc program"
#endif

/** Poll period of the folder; only how often it looks, nothing is asserted on time. */
#define POLL_NS 20000000L

static void rm_rf(const char *dir)
{
    DIR *d = opendir(dir);
    if (!d)
        return;
    struct dirent *e;
    char p[1400];
    while ((e = readdir(d)) != NULL) {
        if (e->d_name[0] == '.' && (!e->d_name[1] || !strcmp(e->d_name, "..")))
            continue;
        snprintf(p, sizeof(p), "%s/%s", dir, e->d_name);
        remove(p);
    }
    closedir(d);
    rmdir(dir);
}

static const char *const eye_files[] = {"left.png", "right.png", "sbs.png", "left.pfm",
                                        "right.pfm"};
#define EYE_FILES (sizeof(eye_files) / sizeof(eye_files[0]))

/** Starts xrsc with stdout and stderr into log + ".out" / ".err". */
static pid_t spawn(const char *const *args, const char *log)
{
    pid_t pid = fork();
    if (pid != 0)
        return pid;
    char p[1200];
    snprintf(p, sizeof(p), "%s.out", log);
    int fo = open(p, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    snprintf(p, sizeof(p), "%s.err", log);
    int fe = open(p, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fo < 0 || fe < 0 || dup2(fo, 1) < 0 || dup2(fe, 2) < 0)
        _exit(126);
    char *argv[32];
    int n = 0;
    argv[n++] = (char *)XRSC_EXE;
    for (; args[n - 1] && n < 31; n++)
        argv[n] = (char *)args[n - 1];
    argv[n] = NULL;
    execv(XRSC_EXE, argv);
    _exit(127);
}

/** Polls until path exists (true) or the child ends first (false, *status set). */
static bool wait_for_file(pid_t pid, const char *path, int *status)
{
    struct stat st;
    for (;;) {
        if (stat(path, &st) == 0)
            return true;
        if (waitpid(pid, status, WNOHANG) == pid)
            return false;
        struct timespec ts = {0, POLL_NS};
        nanosleep(&ts, NULL);
    }
}

static bool png_decodes(const char *path, uint32_t *w, uint32_t *h)
{
    png_image img;
    memset(&img, 0, sizeof(img));
    img.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_file(&img, path))
        return false;
    img.format = PNG_FORMAT_RGB;
    void *buf = malloc(PNG_IMAGE_SIZE(img));
    bool ok = buf && png_image_finish_read(&img, NULL, buf, 0, NULL);
    free(buf);
    *w = img.width;
    *h = img.height;
    if (!ok)
        png_image_free(&img);
    return ok;
}

static char *read_text(const char *path)
{
    size_t n = 0;
    char *b = t_read_file(path, &n);
    char *s = b ? realloc(b, n + 1) : NULL;
    if (!s) {
        free(b);
        return NULL;
    }
    s[n] = '\0';
    return s;
}

/**
 * Every file in dir is whole: none empty, no temporary left, PNGs decode at 32 px per eye
 * (64 side by side), PFMs parse at 32 x 32, frame k present means all its files are; returns
 * the number of complete frames.
 */
static unsigned check_files(const char *dir)
{
    unsigned present[4096][EYE_FILES];
    memset(present, 0, sizeof(present));
    unsigned max_frame = 0, files = 0;
    DIR *d = opendir(dir);
    CHECK(d != NULL);
    if (!d)
        return 0;
    struct dirent *e;
    while ((e = readdir(d)) != NULL) {
        const char *n = e->d_name;
        if (n[0] == '.')
            continue;
        char p[1400];
        snprintf(p, sizeof(p), "%s/%s", dir, n);
        struct stat st;
        CHECK(stat(p, &st) == 0);
        CHECK_MSG(st.st_size > 0, "%s is empty", p);
        CHECK_MSG(!strstr(n, ".tmp"), "%s: a temporary file is left", p);
        unsigned k;
        char part[64];
        if (sscanf(n, "frame_%5u_%63s", &k, part) != 2 || k >= 4096)
            continue;
        files++;
        for (size_t f = 0; f < EYE_FILES; f++)
            if (!strcmp(part, eye_files[f]))
                present[k][f] = 1;
        if (k > max_frame)
            max_frame = k;
        uint32_t w = 0, h = 0;
        if (strstr(n, ".png")) {
            CHECK_MSG(png_decodes(p, &w, &h), "%s does not decode", p);
            CHECK_MSG(h == 32 && w == (strstr(n, "_sbs") ? 64u : 32u), "%s: %ux%u", p, w, h);
        } else if (strstr(n, ".pfm")) {
            float *px = NULL;
            xrsc_diag diag = {0};
            CHECK_MSG(hs_read_pfm(p, &px, &w, &h, &diag) == XRSC_OK, "%s: %s", p, diag.message);
            CHECK(w == 32 && h == 32);
            free(px);
        }
    }
    closedir(d);
    unsigned complete = 0;
    for (unsigned k = 0; k <= max_frame && files; k++) {
        unsigned have = 0;
        for (size_t f = 0; f < EYE_FILES; f++)
            have += present[k][f];
        CHECK_MSG(have == 0 || have == EYE_FILES, "frame %u has %u of its %zu files", k, have,
                  EYE_FILES);
        complete += have == EYE_FILES;
    }
    return complete;
}

