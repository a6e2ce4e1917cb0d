// SPDX-License-Identifier: MIT
/**
 * @file test_cli_ctrlc.c
 * @brief Safe runs (issue 11): `xrsc` started as a child with many frames, signalled once its
 *        first frame is on disk (the folder is polled; no time is asserted), must finish the
 *        frame in flight, exit 128 + signal, print its summary, and leave only whole files:
 *        every PNG decodes, every PFM parses, frames are complete sets, run.json says
 *        "interrupted". Both the direct path and the OpenXR path (host_sim's runtime); SIGINT,
 *        SIGTERM and SIGHUP (issue 23).
 */
#include "t_cli_run.h"

#ifndef XRSC_TEST_OUT
#error "XRSC_TEST_OUT: a scratch folder"
#endif

/** Frames asked for: far more than are rendered before the signal (the test never waits for
 *  them; a run that ignored the signal would run into ctest's timeout). */
#define MANY_FRAMES "100000"

/** One stopped run: path "direct" or "openxr", signal sig. */
static void stopped_run(const char *name, bool direct, int sig)
{
    char dir[1024], log[1100], first[1200];
    snprintf(dir, sizeof(dir), "%s/%s", XRSC_TEST_OUT, name);
    snprintf(log, sizeof(log), "%s/%s", XRSC_TEST_OUT, name);
    rm_rf(dir);
    const char *args[] = {"--direct",        "--spp",        "1",     "--frames",
                          MANY_FRAMES,       "--resolution", "32x32", "--write",
                          "eyes,sbs,linear", "--out",        dir,     NULL};
    /* The OpenXR path does not show a session's frame 0: its files start at frame 1. */
    snprintf(first, sizeof(first), "%s/frame_%05u_sbs.png", dir, direct ? 0u : 1u);
    pid_t pid = spawn(direct ? args : args + 1, log);
    CHECK(pid > 0);
    int status = 0;
    bool appeared = wait_for_file(pid, first, &status);
    CHECK_MSG(appeared, "%s: xrsc ended (status %d) before writing %s", name, status, first);
    if (appeared) {
        CHECK(kill(pid, sig) == 0);
        CHECK(waitpid(pid, &status, 0) == pid);
    }
    CHECK_MSG(WIFEXITED(status) && WEXITSTATUS(status) == 128 + sig, "%s: status %d", name, status);
    char p[1200];
    snprintf(p, sizeof(p), "%s.out", log);
    char *out = read_text(p);
    snprintf(p, sizeof(p), "%s.err", log);
    char *err = read_text(p);
    /* The summary (stdout) and the stop notice (stderr). */
    CHECK_MSG(out && strstr(out, "\nframes: ") && strstr(out, "output: "), "%s stdout: %s", name,
              out ? out : "(none)");
    const char *sig_name = sig == SIGINT ? "SIGINT" : sig == SIGHUP ? "SIGHUP" : "SIGTERM";
    CHECK_MSG(err && strstr(err, sig_name) && strstr(err, "stopped after"), "%s stderr: %s", name,
              err ? err : "(none)");
    unsigned frames = check_files(dir);
    CHECK_MSG(frames >= 1, "%s: no complete frame", name);
    /* run.json: whole, the stop recorded, the summary's frame count as on disk, and no
     * validation errors (the test runs with XRSC_VALIDATION=1). */
    snprintf(p, sizeof(p), "%s/run.json", dir);
    char *json = read_text(p);
    CHECK_MSG(json != NULL, "%s: run.json missing", name);
    if (json) {
        char want[96];
        size_t n = strlen(json);
        CHECK(json[0] == '{' && n > 3 && !strcmp(json + n - 2, "}\n"));
        CHECK(strstr(json, "\"status\": \"interrupted\"") != NULL);
        snprintf(want, sizeof(want), "\"signal\": \"%s\"", sig_name);
        CHECK(strstr(json, want) != NULL);
        snprintf(want, sizeof(want), "\"exit_code\": %d", 128 + sig);
        CHECK(strstr(json, want) != NULL);
        snprintf(want, sizeof(want), "\"summary\": {\n    \"frames\": %u,", frames);
        CHECK_MSG(strstr(json, want) != NULL, "%s: run.json does not say %u frames", name, frames);
        CHECK(strstr(json, "\"validation_errors\": 0,") != NULL);
        CHECK(strstr(json, "\"start_time_utc\": \"20") != NULL);
        CHECK(strstr(json, "\"device\": \"") != NULL);
    }
    printf("  %s: exit %d after %u complete frames\n", name, WEXITSTATUS(status), frames);
    free(json);
    free(out);
    free(err);
}

static void t_direct_sigint(void)
{
    stopped_run("direct_sigint", true, SIGINT);
}

static void t_openxr_sigint(void)
{
    stopped_run("openxr_sigint", false, SIGINT);
}

static void t_direct_sigterm(void)
{
    stopped_run("direct_sigterm", true, SIGTERM);
}

/* Issue 23: a closed terminal (SIGHUP) is a clean stop as well, frames.csv renamed into place. */
static void t_openxr_sighup(void)
{
    stopped_run("openxr_sighup", false, SIGHUP);
    char p[1200];
    snprintf(p, sizeof(p), "%s/openxr_sighup/frames.csv", XRSC_TEST_OUT);
    struct stat st;
    CHECK_MSG(stat(p, &st) == 0 && st.st_size > 0, "%s is missing", p);
}

int main(void)
{
    mkdir(XRSC_TEST_OUT, 0777);
    RUN(t_direct_sigint);
    RUN(t_openxr_sigint);
    RUN(t_direct_sigterm);
    RUN(t_openxr_sighup);
    return t_finish();
}
