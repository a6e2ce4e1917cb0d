#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# @file build.sh
# @brief Installs what is missing, then configures and builds xrsc into build/ (incremental).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/install-deps.sh"
cmake -S "$root" -B "$root/build" -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build "$root/build" -j"$(nproc)"
