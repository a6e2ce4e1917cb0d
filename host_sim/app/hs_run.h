// SPDX-License-Identifier: MIT
/**
 * @file hs_run.h
 * @brief What `xrsc replay` keeps around a run: Ctrl-C/SIGTERM as a clean stop, an output
 *        folder that never mixes two runs, and the run's record (run.json, run.conf), so a
 *        replay can be repeated exactly (`xrsc --config DIR/run.conf --out NEW`).
 */
#pragma once

#include "hs_replay.h"

#include <signal.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

#ifdef __cplusplus
extern "C" {
#endif

/** The record's files in the output folder. */
#define HS_RUN_JSON "run.json"
#define HS_RUN_CONF "run.conf"

/**
 * Installs handlers of SIGINT, SIGTERM and SIGHUP (sigaction, SA_RESTART). The first signal
 * only stores its number in a volatile sig_atomic_t, returned here for
 * hs_replay_options.stop: the run stops cleanly after the frame in flight. A second signal
 * (a second Ctrl-C) ends the process at once: once the "running" record is written
 * (hs_run_write_record) it rewrites run.json in place as "interrupted" by that signal (text
 * prepared beforehand), renames frames.csv.tmp into place when it holds whole rows (else
 * removes it), removes the run's other temporary files (a frame set in flight) and exits
 * with 128 + signal, with async-signal-safe calls only, on the main thread (another thread
 * that gets it passes it on); before that record, it ends the process as the signal would.
 * SIGXFSZ is ignored, so a file size limit (RLIMIT_FSIZE) is a write error (EFBIG) that the
 * run reports rather than the end of the process.
 */
const volatile sig_atomic_t *hs_run_catch_signals(void);

/** The exit status of a run stopped by signal sig: 128 + sig (SIGINT 130, SIGTERM 143). */
int hs_run_exit_status(int sig);

/** "SIGINT", "SIGTERM", "SIGHUP" or "signal N". */
const char *hs_run_signal_name(int sig, char *buf, size_t size);

/**
 * Makes the output folder ready (mkdir -p). A folder holding files of an earlier run (those
 * this program writes: frame_NNNNN_*.png/.pfm/.exr, frames.csv, views.csv, run.json, run.conf,
 * and their .tmp leftovers) is refused with XRSC_ERROR_INVALID_ARGUMENT (field "--out", naming one of
 * them and their count) unless overwrite, which removes exactly those files first; any other
 * file is left alone and does not count.
 */
xrsc_result hs_run_prepare_out(const char *dir, bool overwrite, xrsc_diag *diag);

/** An option's value when it is not given: the program's default, as it would be typed. */
typedef struct hs_run_setting {
    const char *key;   /**< "--resolution" */
    const char *value; /**< "256x256" */
} hs_run_setting;

/** Everything the record says besides the run's statistics. */
typedef struct hs_run_info {
    int argc; /**< the command line as typed */
    char *const *argv;
    int args_argc; /**< after hs_args_prepare (config files expanded, --x=y split) */
    char *const *args_argv;
    const char *const *value_options; /**< the command's options that take a value */
    size_t value_count;
    const hs_run_setting *defaults; /**< values of options not given (program defaults) */
    size_t default_count;
    /** Options that change nothing in the result (--quiet, --overwrite): not settings. */
    const char *const *not_settings;
    size_t not_settings_count;
    const char *out_dir;
    char start_utc[32]; /**< ISO 8601, e.g. 2026-11-25T06:40:00Z (hs_run_info_start) */
} hs_run_info;

/** Sets info->start_utc to the current time. */
void hs_run_info_start(hs_run_info *info);

/**
 * Writes run.json into info->out_dir, whole (hs_file.h). run.json: program and version, the
 * command line as typed and as parsed, the settings (every option given, by its last value,
 * and the defaults of those not given; flags given are true; options left to the library's
 * defaults are listed under "library_defaults"), the device, the start time, the status
 * ("running", "completed", "interrupted", "failed"), the signal, exit code, error (a failed
 * run's, as printed) and with st the run's summary.
 *
 * status "running" is written before the run (st NULL), with run.conf (the same settings in
 * --config format, out commented out) and a blank reserve of whitespace at its end; it also
 * prepares the record a second signal writes (hs_run_catch_signals) and keeps the folder
 * open. The final status is written after the run through that descriptor (so the record
 * follows a folder moved during the run), after the run's temporary files are settled as a
 * second signal would (frames.csv.tmp renamed into place when whole, others removed); when no
 * new file can be written (a full disk) it is written in place over the running record,
 * within its reserve.
 */
xrsc_result hs_run_write_record(const hs_run_info *info, const hs_replay_stats *st,
                                const char *status, int exit_code, const char *error,
                                xrsc_diag *diag);

/** After the final record: a second signal no longer rewrites run.json. */
void hs_run_disarm(void);

/** Prints the program's version and the Vulkan/OpenXR versions it uses (xrsc --version). */
void hs_run_print_version(FILE *f);

#ifdef __cplusplus
}
#endif
