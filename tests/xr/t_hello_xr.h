// SPDX-License-Identifier: MIT
/**
 * @file t_hello_xr.h
 * @brief What the tests that run Debian's hello_xr against the runtime share: a monotonic
 *        clock, an emptied output folder, and the child side of starting hello_xr.
 *
 * Needs XRSC_TEST_OUT, XRSC_RUNTIME_JSON and XRSC_HELLO_XR (compile definitions).
 */
#pragma once

#include <dirent.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

static inline double t_now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

/** Creates dir (and XRSC_TEST_OUT) and removes the files in it. */
static inline void t_clean_dir(const char *dir)
{
    mkdir(XRSC_TEST_OUT, 0777);
    mkdir(dir, 0777);
    DIR *d = opendir(dir);
    if (!d)
        return;
    struct dirent *e;
    char p[1024];
    while ((e = readdir(d))) {
        if (e->d_name[0] == '.')
            continue;
        snprintf(p, sizeof(p), "%s/%s", dir, e->d_name);
        unlink(p);
    }
    closedir(d);
}

/**
 * In the forked child: stdin from the pipe in[] (hello_xr waits there for a key to quit),
 * stdout and stderr to log_path, no display (env may set one), the runtime's manifest, fast
 * pace, then env ("NAME=value", NULL-terminated; "NAME=" unsets), and exec hello_xr -g
 * graphics. Does not return.
 */
static inline void t_exec_hello(const char *graphics, const char *const *env, const char *log_path,
                                const int in[2])
{
    int fd = open(log_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    dup2(in[0], 0);
    dup2(fd, 1);
    dup2(fd, 2);
    close(in[1]);
    unsetenv("DISPLAY"); /* headless */
    unsetenv("WAYLAND_DISPLAY");
    setenv("XR_RUNTIME_JSON", XRSC_RUNTIME_JSON, 1);
    setenv("XRSC_RT_PACE", "fast", 1);
    for (const char *const *e = env; e && *e; e++) {
        char name[128];
        const char *eq = strchr(*e, '=');
        snprintf(name, sizeof(name), "%.*s", (int)(eq - *e), *e);
        if (eq[1])
            setenv(name, eq + 1, 1);
        else
            unsetenv(name);
    }
    execl(XRSC_HELLO_XR, "hello_xr", "-g", graphics, (char *)NULL);
    _exit(127);
}
