// SPDX-License-Identifier: MIT
/**
 * @file hs_run.c
 * @brief A run's signals, output folder and record (hs_run.h).
 */
#define _GNU_SOURCE /* syscall(SYS_getdents64) in the signal handler */
#include "hs_run.h"

#include "hs_args.h"
#include "hs_file.h"
#include "u_diag.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <openxr/openxr.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <time.h>
#include <unistd.h>
#include <vulkan/vulkan.h>

#ifndef XRSC_VERSION
#define XRSC_VERSION "unknown"
#endif

/* ---- signals ---- */

/** The signals handled, each with its record for a second signal: SIGINT, SIGTERM, SIGHUP. */
#define HS_RUN_SIGNALS 3
/** Room left in the "running" run.json (blank padding after it) for the final record's
 *  summary, device and error, so that it can be written in place on a full disk. */
#define HS_RUN_JSON_RESERVE 4096
/** Largest run.json (the settings, the summary and the reserve). */
#define HS_RUN_JSON_MAX 32768

/**
 * What a signal handler needs, prepared beforehand: the program's one process-wide state (a
 * handler can reach nothing else). `signal` is read by the frame loops (hs_replay_options.stop).
 * The rest serves a second signal: the output folder, and run.json's text saying "interrupted"
 * by each handled signal, written with async-signal-safe calls only (hs_run.h).
 */
static struct {
    volatile sig_atomic_t signal;
    volatile sig_atomic_t armed; /**< 1 while the records below are ready */
    pthread_t main_thread;
    int dir_fd; /**< the output folder, opened with the running record; -1 before */
    char record[HS_RUN_SIGNALS][HS_RUN_JSON_MAX];
    size_t record_len[HS_RUN_SIGNALS];
} hs_run_state = {.dir_fd = -1};

static const int handled_signals[HS_RUN_SIGNALS] = {SIGINT, SIGTERM, SIGHUP};

static int signal_slot(int sig)
{
    for (int i = 0; i < HS_RUN_SIGNALS; i++)
        if (handled_signals[i] == sig)
            return i;
    return 0;
}

/** Whether name (NUL-terminated) ends with suffix. */
static bool ends_with(const char *name, const char *suffix)
{
    size_t n = strlen(name), s = strlen(suffix);
    return n >= s && !strcmp(name + n - s, suffix);
}

static bool is_run_file(const char *name);

/* Async-signal-safe from here to the handler: openat, pread, pwrite, ftruncate, renameat,
 * unlinkat, close, getdents64, _exit; no stdio, no malloc. All relative to the output folder's
 * descriptor, so the record follows the folder if it is moved during the run. */

/* frames.csv.tmp: renamed into place when it holds whole rows (it is flushed row by row), else
 * removed. Any other temporary file of the run is removed: its frame set is not whole. */
static void settle_temp(int dir, const char *name)
{
    if (!strcmp(name, "frames.csv" HS_TEMP_SUFFIX)) {
        int fd = openat(dir, name, O_RDONLY | O_CLOEXEC);
        struct stat st;
        char last = 0;
        bool whole = fd >= 0 && fstat(fd, &st) == 0 && st.st_size > 0 &&
                     pread(fd, &last, 1, st.st_size - 1) == 1 && last == '\n';
        if (fd >= 0)
            close(fd);
        if (whole && renameat(dir, name, dir, "frames.csv") == 0)
            return;
    }
    unlinkat(dir, name, 0);
}

static void settle_temps(int dir)
{
    int fd = openat(dir, ".", O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0)
        return;
    char buf[4096];
    long n;
    while ((n = syscall(SYS_getdents64, fd, buf, sizeof(buf))) > 0) {
        for (long off = 0; off < n;) {
            /* struct linux_dirent64: ino 8, off 8, reclen 2, type 1, name */
            unsigned short reclen;
            memcpy(&reclen, buf + off + 16, sizeof(reclen));
            const char *name = buf + off + 19;
            if (ends_with(name, HS_TEMP_SUFFIX) && is_run_file(name))
                settle_temp(dir, name);
            off += reclen;
        }
    }
    close(fd);
}

static bool write_all(int fd, const char *text, size_t len)
{
    size_t done = 0;
    while (done < len) {
        ssize_t w = pwrite(fd, text + done, len - done, (off_t)done);
        if (w <= 0)
            return false;
        done += (size_t)w;
    }
    return true;
}

/* run.json rewritten in place (no new file: the disk may be full), cut to its new length. */
static bool write_in_place(int dir, const char *text, size_t len)
{
    int fd = openat(dir, HS_RUN_JSON, O_WRONLY | O_CLOEXEC);
    if (fd < 0)
        return false;
    bool ok = write_all(fd, text, len) && ftruncate(fd, (off_t)len) == 0;
    close(fd);
    return ok;
}

/* run.json replaced whole (temporary file, then renameat); *err: errno of a failure. */
static bool write_whole(int dir, const char *text, size_t len, int *err)
{
    const char *tmp = HS_RUN_JSON HS_TEMP_SUFFIX;
    int fd = openat(dir, tmp, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
    bool ok = fd >= 0 && write_all(fd, text, len);
    *err = ok ? 0 : errno;
    if (fd >= 0 && close(fd) != 0 && ok) {
        ok = false;
        *err = errno;
    }
    if (ok && renameat(dir, tmp, dir, HS_RUN_JSON) != 0) {
        ok = false;
        *err = errno;
    }
    if (!ok)
        unlinkat(dir, tmp, 0);
    return ok;
}

static void on_signal(int sig)
{
    if (!hs_run_state.signal) { /* the first: a clean stop after the frame in flight */
        hs_run_state.signal = sig;
        return;
    }
    if (!hs_run_state.armed) { /* no record to keep: end as the signal would */
        signal(sig, SIG_DFL);
        raise(sig);
        return;
    }
    /* The second: end now. Done on the main thread, which then writes nothing more. */
    if (!pthread_equal(pthread_self(), hs_run_state.main_thread)) {
        pthread_kill(hs_run_state.main_thread, sig);
        return;
    }
    hs_run_state.armed = 0;
    static const char notice[] = "xrsc: a second signal: ended at once; run.json says "
                                 "interrupted, the files written are whole\n";
    ssize_t ignored = write(STDERR_FILENO, notice, sizeof(notice) - 1);
    (void)ignored;
    int slot = signal_slot(sig);
    settle_temps(hs_run_state.dir_fd);
    write_in_place(hs_run_state.dir_fd, hs_run_state.record[slot], hs_run_state.record_len[slot]);
    _exit(hs_run_exit_status(sig));
}

const volatile sig_atomic_t *hs_run_catch_signals(void)
{
    struct sigaction sa;
    memset(&sa, 0, sizeof(sa));
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    for (int i = 0; i < HS_RUN_SIGNALS; i++)
        sigaddset(&sa.sa_mask, handled_signals[i]); /* one handler at a time */
    /* SA_RESTART: writes and waits in flight go on. */
    sa.sa_flags = SA_RESTART;
    hs_run_state.main_thread = pthread_self();
    for (int i = 0; i < HS_RUN_SIGNALS; i++)
        sigaction(handled_signals[i], &sa, NULL);
    /* A file size limit (RLIMIT_FSIZE) makes a write fail with EFBIG, an error the run
     * reports, instead of ending the process. */
    signal(SIGXFSZ, SIG_IGN);
    return &hs_run_state.signal;
}

int hs_run_exit_status(int sig)
{
    return 128 + sig;
}

const char *hs_run_signal_name(int sig, char *buf, size_t size)
{
    if (sig == SIGINT)
        snprintf(buf, size, "SIGINT");
    else if (sig == SIGTERM)
        snprintf(buf, size, "SIGTERM");
    else if (sig == SIGHUP)
        snprintf(buf, size, "SIGHUP");
    else
        snprintf(buf, size, "signal %d", sig);
    return buf;
}

/* ---- output folder ---- */

/** A file this program writes: frame_<digits>_<part>.<png|pfm|exr>, frames.csv, views.csv,
 *  run.json, run.conf, each also with HS_TEMP_SUFFIX (a run killed while writing it). */
static bool is_run_file(const char *name)
{
    char base[256];
    size_t n = strlen(name);
    if (n >= sizeof(base))
        return false;
    memcpy(base, name, n + 1);
    if (ends_with(base, HS_TEMP_SUFFIX))
        base[n - strlen(HS_TEMP_SUFFIX)] = '\0';
    if (!strcmp(base, "frames.csv") || !strcmp(base, "views.csv") || !strcmp(base, HS_RUN_JSON) ||
        !strcmp(base, HS_RUN_CONF))
        return true;
    if (strncmp(base, "frame_", 6) != 0)
        return false;
    const char *p = base + 6;
    size_t digits = strspn(p, "0123456789");
    if (digits == 0 || p[digits] != '_')
        return false;
    p += digits + 1;
    size_t part = strspn(p, "abcdefghijklmnopqrstuvwxyz0123456789_-");
    if (part == 0 || p[part] != '.')
        return false;
    p += part;
    return !strcmp(p, ".png") || !strcmp(p, ".pfm") || !strcmp(p, ".exr");
}

xrsc_result hs_run_prepare_out(const char *dir, bool overwrite, xrsc_diag *diag)
{
    xrsc_result res = hs_make_dirs(dir, "--out", diag);
    if (res != XRSC_OK)
        return res;
    DIR *d = opendir(dir);
    if (!d)
        return u_diag_set(diag, XRSC_ERROR_IO, dir, 0, "--out", "cannot list: %s", strerror(errno));
    unsigned found = 0;
    char first[256] = "";
    struct dirent *e;
    while ((e = readdir(d)) != NULL) {
        if (!is_run_file(e->d_name))
            continue;
        if (!found++)
            snprintf(first, sizeof(first), "%s", e->d_name);
        if (!overwrite)
            continue;
        char path[1400];
        snprintf(path, sizeof(path), "%s/%s", dir, e->d_name);
        if (remove(path) != 0 && errno != ENOENT) {
            int err = errno;
            closedir(d);
            return u_diag_set(diag, XRSC_ERROR_IO, path, 0, "--overwrite", "cannot remove: %s",
                              strerror(err));
        }
    }
    closedir(d);
    if (found && !overwrite)
        return u_diag_set(diag, XRSC_ERROR_INVALID_ARGUMENT, dir, 0, "--out",
                          "holds an earlier run (%s and %u more of its files); give --overwrite "
                          "to replace it, or another --out",
                          first, found - 1);
    return XRSC_OK;
}

/* ---- run.json and run.conf ---- */

void hs_run_info_start(hs_run_info *info)
{
    time_t now = time(NULL);
    struct tm tm;
    gmtime_r(&now, &tm);
    strftime(info->start_utc, sizeof(info->start_utc), "%Y-%m-%dT%H:%M:%SZ", &tm);
}

static void json_string(FILE *f, const char *s)
{
    fputc('"', f);
    for (const unsigned char *p = (const unsigned char *)s; *p; p++) {
        if (*p == '"' || *p == '\\')
            fprintf(f, "\\%c", *p);
        else if (*p == '\n')
            fputs("\\n", f);
        else if (*p < 0x20)
            fprintf(f, "\\u%04x", *p);
        else
            fputc(*p, f);
    }
    fputc('"', f);
}

static void json_argv(FILE *f, int argc, char *const *argv)
{
    fputc('[', f);
    for (int i = 0; i < argc; i++) {
        fputs(i ? ", " : "", f);
        json_string(f, argv[i]);
    }
    fputc(']', f);
}

static bool not_setting(const hs_run_info *info, const char *a)
{
    return hs_arg_in(a, info->not_settings, info->not_settings_count);
}

/** The value of option key: its last one in the parsed arguments, else the program default;
 *  NULL when neither (the library's default). */
static const char *setting_value(const hs_run_info *info, const char *key)
{
    const char *v = NULL;
    for (int i = 1; i + 1 < info->args_argc; i++) {
        if (!hs_arg_in(info->args_argv[i], info->value_options, info->value_count))
            continue;
        if (!strcmp(info->args_argv[i], key))
            v = info->args_argv[i + 1];
        i++; /* skip the value */
    }
    for (size_t k = 0; !v && k < info->default_count; k++)
        if (!strcmp(info->defaults[k].key, key))
            v = info->defaults[k].value;
    return v;
}

/** Calls fn for each flag given (an option without a value, not a value), once each. */
static void for_each_flag(const hs_run_info *info, void (*fn)(void *u, const char *flag), void *u)
{
    for (int i = 1; i < info->args_argc; i++) {
        const char *a = info->args_argv[i];
        if (hs_arg_in(a, info->value_options, info->value_count)) {
            i++;
            continue;
        }
        if (a[0] != '-' || a[1] != '-' || not_setting(info, a))
            continue;
        bool seen = false;
        for (int j = 1; j < i; j++)
            seen |= !strcmp(info->args_argv[j], a);
        if (!seen)
            fn(u, a);
    }
}

/** json_settings' state for json_flag. */
typedef struct json_members {
    FILE *f;
    bool first;
} json_members;

static void json_member(json_members *m, const char *key)
{
    fprintf(m->f, "%s\n    ", m->first ? "" : ",");
    json_string(m->f, key);
    fputs(": ", m->f);
    m->first = false;
}

static void json_flag(void *u, const char *flag)
{
    json_member(u, flag + 2);
    fputs("true", ((json_members *)u)->f);
}

static void json_settings(FILE *f, const hs_run_info *info)
{
    json_members m = {.f = f, .first = true};
    fputs("{", f);
    for (size_t k = 0; k < info->value_count; k++) {
        const char *key = info->value_options[k];
        const char *v = setting_value(info, key);
        if (!v || not_setting(info, key))
            continue;
        json_member(&m, key + 2);
        json_string(f, v);
    }
    for_each_flag(info, json_flag, &m);
    fputs("\n  }", f);
}

static void json_summary(FILE *f, const hs_replay_stats *st)
{
    fprintf(f,
            "{\n    \"frames\": %u,\n    \"load_s\": %.6g,\n    \"total_s\": %.6g,\n"
            "    \"render_ms_mean\": %.6g,\n    \"render_ms_max\": %.6g,\n"
            "    \"rays_per_frame\": %.6g,\n    \"validation_errors\": %u,\n"
            "    \"pass_gpu_ms_mean\": {",
            st->frames, st->load_s, st->total_s, st->render_ms_mean, st->render_ms_max,
            st->rays_per_frame, st->validation_errors);
    for (uint32_t p = 0; p < st->pass_count; p++) {
        fprintf(f, "%s", p ? ", " : "");
        json_string(f, st->pass_mean[p].name ? st->pass_mean[p].name : "?");
        fprintf(f, ": %.6g", st->pass_mean[p].gpu_ms);
    }
    fputs("}\n  }", f);
}

/** run.json without its last newline; sig: the signal that stopped the run (0: none); error:
 *  a failed run's error (NULL: none). */
static void write_json(FILE *f, const hs_run_info *info, const hs_replay_stats *st,
                       const char *status, int exit_code, int sig, const char *error)
{
    fputs("{\n  \"program\": \"xrsc\",\n  \"version\": ", f);
    json_string(f, XRSC_VERSION);
    fputs(",\n  \"command_line\": ", f);
    json_argv(f, info->argc, info->argv);
    fputs(",\n  \"arguments\": ", f);
    json_argv(f, info->args_argc > 0 ? info->args_argc - 1 : 0, info->args_argv + 1);
    fputs(",\n  \"start_time_utc\": ", f);
    json_string(f, info->start_utc);
    fputs(",\n  \"settings\": ", f);
    json_settings(f, info);
    fputs(",\n  \"library_defaults\": [", f);
    bool first = true;
    for (size_t k = 0; k < info->value_count; k++) {
        const char *key = info->value_options[k];
        if (setting_value(info, key) || not_setting(info, key))
            continue;
        fputs(first ? "" : ", ", f);
        json_string(f, key + 2);
        first = false;
    }
    fputs("],\n  \"device\": ", f);
    if (st && st->device[0])
        json_string(f, st->device);
    else
        fputs("null", f);
    fputs(",\n  \"status\": ", f);
    json_string(f, status);
    char name[32];
    fputs(",\n  \"signal\": ", f);
    if (sig)
        json_string(f, hs_run_signal_name(sig, name, sizeof(name)));
    else
        fputs("null", f);
    fputs(",\n  \"exit_code\": ", f);
    if (strcmp(status, "running") != 0)
        fprintf(f, "%d", exit_code);
    else
        fputs("null", f);
    fputs(",\n  \"error\": ", f);
    if (error)
        json_string(f, error);
    else
        fputs("null", f);
    fputs(",\n  \"summary\": ", f);
    if (st)
        json_summary(f, st);
    else
        fputs("null", f);
    fputs("\n}", f);
}

/** The whole text of run.json (malloc'ed, *len bytes); running: with the blank reserve. */
static char *render_json(const hs_run_info *info, const hs_replay_stats *st, const char *status,
                         int exit_code, int sig, const char *error, size_t *len)
{
    char *text = NULL;
    FILE *m = open_memstream(&text, len);
    if (!m)
        return NULL;
    write_json(m, info, st, status, exit_code, sig, error);
    if (!strcmp(status, "running")) /* blank JSON whitespace: room for the final record */
        fprintf(m, "%*s", HS_RUN_JSON_RESERVE, "");
    fputc('\n', m);
    if (fclose(m) != 0) {
        free(text);
        return NULL;
    }
    return text;
}

/** Prepares what a second signal writes: run.json "interrupted" by each handled signal. */
static void arm_second_signal(const hs_run_info *info)
{
    hs_run_state.armed = 0;
    for (int i = 0; i < HS_RUN_SIGNALS; i++) {
        int sig = handled_signals[i];
        size_t len = 0;
        char *text =
            render_json(info, NULL, "interrupted", hs_run_exit_status(sig), sig, NULL, &len);
        if (!text || len > sizeof(hs_run_state.record[i])) {
            free(text);
            return;
        }
        memcpy(hs_run_state.record[i], text, len);
        hs_run_state.record_len[i] = len;
        free(text);
    }
    hs_run_state.armed = hs_run_state.dir_fd >= 0;
}

/** A config value, double-quoted when it has blanks, '#', '"', '\' or is empty. */
static void conf_value(FILE *f, const char *v)
{
    if (*v && !strpbrk(v, " \t#\"\\")) {
        fputs(v, f);
        return;
    }
    fputc('"', f);
    for (const char *p = v; *p; p++) {
        if (*p == '"' || *p == '\\')
            fputc('\\', f);
        fputc(*p, f);
    }
    fputc('"', f);
}

static void conf_flag(void *u, const char *flag)
{
    fprintf((FILE *)u, "%s\n", flag + 2);
}

static void write_conf(FILE *f, const hs_run_info *info)
{
    fprintf(f,
            HS_ARGS_RECORD_HEAD "%s" HS_ARGS_RECORD_MARK
            "%s: its settings in --config format (xrsc --help).\n"
            "# Repeat it with: xrsc --config %s/" HS_RUN_CONF " --out NEW_FOLDER\n",
            XRSC_VERSION, info->start_utc, info->out_dir);
    for (size_t k = 0; k < info->value_count; k++) {
        const char *key = info->value_options[k];
        const char *v = setting_value(info, key);
        if (!v || not_setting(info, key))
            continue;
        bool out = !strcmp(key, "--out");
        fprintf(f, "%s%s = ", out ? "# " : "", key + 2);
        conf_value(f, v);
        fputs(out ? "   (give --out)\n" : "\n", f);
    }
    for_each_flag(info, conf_flag, f);
}

/* The final record, through the folder's descriptor: whole, else in place (full disk). The
 * run's temporary files are settled first, as a second signal would. */
static xrsc_result write_final(const char *path, const char *text, size_t len, xrsc_diag *diag)
{
    int dir = hs_run_state.dir_fd, err = 0;
    settle_temps(dir);
    if (write_whole(dir, text, len, &err) || write_in_place(dir, text, len))
        return XRSC_OK;
    return u_diag_set(diag, XRSC_ERROR_IO, path, 0, "", "cannot write the run's record: %s",
                      strerror(err));
}

xrsc_result hs_run_write_record(const hs_run_info *info, const hs_replay_stats *st,
                                const char *status, int exit_code, const char *error,
                                xrsc_diag *diag)
{
    char path[HS_OUT_PATH_MAX];
    bool running = !strcmp(status, "running");
    snprintf(path, sizeof(path), "%s/" HS_RUN_JSON, info->out_dir);
    size_t len = 0;
    char *text = render_json(info, st, status, exit_code, st ? st->stopped_by : 0, error, &len);
    if (!text)
        return u_diag_set(diag, XRSC_ERROR_OUT_OF_MEMORY, path, 0, "", "cannot format");
    xrsc_result res;
    if (!running && hs_run_state.dir_fd >= 0) {
        res = write_final(path, text, len, diag);
        free(text);
        return res;
    }
    hs_out_file out;
    if ((res = hs_out_open(&out, path, diag)) == XRSC_OK) {
        fwrite(text, 1, len, out.f);
        res = hs_out_close(&out, true, diag);
    }
    free(text);
    if (res != XRSC_OK || !running)
        return res;
    /* run.conf: the settings, the same before and after the run. */
    snprintf(path, sizeof(path), "%s/" HS_RUN_CONF, info->out_dir);
    if ((res = hs_out_open(&out, path, diag)) != XRSC_OK)
        return res;
    write_conf(out.f, info);
    if ((res = hs_out_close(&out, true, diag)) != XRSC_OK)
        return res;
    if (hs_run_state.dir_fd < 0)
        hs_run_state.dir_fd = open(info->out_dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    arm_second_signal(info);
    return XRSC_OK;
}

void hs_run_disarm(void)
{
    hs_run_state.armed = 0;
    if (hs_run_state.dir_fd >= 0)
        close(hs_run_state.dir_fd);
    hs_run_state.dir_fd = -1;
}

/* ---- --version ---- */

void hs_run_print_version(FILE *f)
{
    fprintf(f, "xrsc %s\n", XRSC_VERSION);
    /* The loader's own version (1.1+ loaders answer vkEnumerateInstanceVersion); cheap: no
     * instance, no device. */
    uint32_t v = VK_API_VERSION_1_0;
    if (vkEnumerateInstanceVersion(&v) == VK_SUCCESS)
        fprintf(f, "Vulkan loader %u.%u.%u\n", VK_API_VERSION_MAJOR(v), VK_API_VERSION_MINOR(v),
                VK_API_VERSION_PATCH(v));
    /* The OpenXR loader has no version query before an instance exists: the API version of
     * the headers this program was built with. */
    fprintf(f, "OpenXR %u.%u.%u (API of the headers built with)\n",
            (unsigned)XR_VERSION_MAJOR(XR_CURRENT_API_VERSION),
            (unsigned)XR_VERSION_MINOR(XR_CURRENT_API_VERSION),
            (unsigned)XR_VERSION_PATCH(XR_CURRENT_API_VERSION));
}
