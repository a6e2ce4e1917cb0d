#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
# @file test-times.py
# @brief CPU seconds (user + sys of a test and every child it waits for) of each ctest test, with
#        a cold Mesa shader cache and then warm (issue 22 item 4; tests/times.md).
#
# Usage: scripts/test-times.py BUILD_DIR [-R REGEX] [-E REGEX] [-L LABEL] [-j N] [--warm-only]
#                              [--order FILE] > times.tsv
#
# CPU time, not wall time, because the machine these numbers come from is shared: its load
# stretches wall time but leaves a test's own CPU time about the same, and on an idle 2-core
# machine a test's wall time is about its CPU time or less. Each test runs as ctest would run it
# (its command, working directory and ENVIRONMENT property, read from `ctest --show-only=json-v1`)
# but without ctest's wall-clock TIMEOUT, which a loaded machine would hit.
#
# Cold: a fresh, empty MESA_SHADER_CACHE_DIR and XDG_CACHE_HOME (the validation layer's shader
# validation cache) per test, as on a fresh CI machine: lavapipe compiles every pipeline. Warm:
# the same test again with the cache its cold run filled. --warm-only skips the cold run and
# uses the user's own caches.
import argparse
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import threading
import time


def tests_of(build, regex, exclude, label):
    out = subprocess.run(["ctest", "--test-dir", build, "--show-only=json-v1"],
                         check=True, capture_output=True, text=True).stdout
    found = []
    for t in json.loads(out)["tests"]:
        props = {p["name"]: p["value"] for p in t.get("properties", [])}
        if regex and not re.search(regex, t["name"]):
            continue
        if exclude and re.search(exclude, t["name"]):
            continue
        if label and label not in props.get("LABELS", []):
            continue
        env = dict(os.environ)
        for kv in props.get("ENVIRONMENT", []):
            k, _, v = kv.partition("=")
            env[k] = v
        found.append((t["name"], t["command"], props.get("WORKING_DIRECTORY", build), env))
    return found


def run_once(command, cwd, env):
    """Run one test; return (exit status, CPU s of it and its waited-for children, wall s)."""
    start = time.monotonic()
    proc = subprocess.Popen(command, cwd=cwd, env=env, stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL)
    _, status, usage = os.wait4(proc.pid, 0)
    proc.returncode = os.waitstatus_to_exitcode(status)
    return proc.returncode, usage.ru_utime + usage.ru_stime, time.monotonic() - start


def measure(test, warm_only, lock):
    name, command, cwd, env = test
    runs = []
    if warm_only:
        runs.append(("warm",) + run_once(command, cwd, env))
    else:
        cache = tempfile.mkdtemp(prefix="xrsc-cold-cache-")
        env = dict(env, MESA_SHADER_CACHE_DIR=cache, XDG_CACHE_HOME=cache)
        try:
            runs.append(("cold",) + run_once(command, cwd, env))
            runs.append(("warm",) + run_once(command, cwd, env))
        finally:
            shutil.rmtree(cache, ignore_errors=True)
    with lock:
        for mode, rc, cpu, wall in runs:
            print(f"{name}\t{mode}\t{rc}\t{cpu:.2f}\t{wall:.1f}", flush=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("build")
    ap.add_argument("-R", dest="regex")
    ap.add_argument("-E", dest="exclude")
    ap.add_argument("-L", dest="label")
    ap.add_argument("-j", dest="jobs", type=int, default=1)
    ap.add_argument("--warm-only", action="store_true")
    ap.add_argument("--order", help="a file of test names, one a line: run those first, in order")
    args = ap.parse_args()
    queue = tests_of(os.path.abspath(args.build), args.regex, args.exclude, args.label)
    if args.order:
        with open(args.order) as f:
            rank = {n.strip(): i for i, n in enumerate(f) if n.strip()}
        queue.sort(key=lambda t: rank.get(t[0], len(rank)))
    print("test\tcache\texit\tcpu_s\twall_s", flush=True)
    lock = threading.Lock()

    def worker():
        while True:
            with lock:
                if not queue:
                    return
                test = queue.pop(0)
            measure(test, args.warm_only, lock)

    threads = [threading.Thread(target=worker) for _ in range(max(1, args.jobs))]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    return 0


if __name__ == "__main__":
    sys.exit(main())
