// SPDX-License-Identifier: MIT
/**
 * @file hs_run.c
 * @brief A run's signals, output folder and record (hs_run.h).
 */
#include "hs_run.h"

#include "hs_args.h"
#include "hs_file.h"
#include "u_diag.h"

#include <dirent.h>
#include <errno.h>
#include <openxr/openxr.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <vulkan/vulkan.h>

#ifndef XRSC_VERSION
#define XRSC_VERSION "unknown"
#endif

/** Set by the handler, read by the frame loops (hs_replay_options.stop). The program's one
 *  process-wide variable: a signal handler can reach nothing else. */
static volatile sig_atomic_t hs_run_signal;

static void on_signal(int sig)
{
    hs_run_signal = sig;
}

const volatile sig_atomic_t *hs_run_catch_signals(void)
{
    struct sigaction sa;
    memset(&sa, 0, sizeof(sa));
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    /* SA_RESTART: writes and waits in flight go on; SA_RESETHAND: a second signal is not
     * caught, so a second Ctrl-C ends a run that does not stop. */
    sa.sa_flags = SA_RESTART | SA_RESETHAND;
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
    return &hs_run_signal;
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
    else
        snprintf(buf, size, "signal %d", sig);
    return buf;
}

/* ---- output folder ---- */

/** Whether name ends with suffix. */
static bool ends_with(const char *name, const char *suffix)
{
    size_t n = strlen(name), s = strlen(suffix);
    return n >= s && !strcmp(name + n - s, suffix);
}

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

static void write_json(FILE *f, const hs_run_info *info, const hs_replay_stats *st,
                       const char *status, int exit_code)
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
    char sig[32];
    fputs(",\n  \"signal\": ", f);
    if (st && st->stopped_by)
        json_string(f, hs_run_signal_name(st->stopped_by, sig, sizeof(sig)));
    else
        fputs("null", f);
    fputs(",\n  \"exit_code\": ", f);
    if (st)
        fprintf(f, "%d", exit_code);
    else
        fputs("null", f);
    fputs(",\n  \"summary\": ", f);
    if (st)
        json_summary(f, st);
    else
        fputs("null", f);
    fputs("\n}\n", f);
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
            "# xrsc %s, run started %s: its settings in --config format (xrsc --help).\n"
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

xrsc_result hs_run_write_record(const hs_run_info *info, const hs_replay_stats *st,
                                const char *status, int exit_code, xrsc_diag *diag)
{
    char path[1200];
    hs_out_file out;
    snprintf(path, sizeof(path), "%s/" HS_RUN_JSON, info->out_dir);
    xrsc_result res = hs_out_open(&out, path, diag);
    if (res != XRSC_OK)
        return res;
    write_json(out.f, info, st, status, exit_code);
    if ((res = hs_out_close(&out, true, diag)) != XRSC_OK)
        return res;
    snprintf(path, sizeof(path), "%s/" HS_RUN_CONF, info->out_dir);
    if ((res = hs_out_open(&out, path, diag)) != XRSC_OK)
        return res;
    write_conf(out.f, info);
    return hs_out_close(&out, true, diag);
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
