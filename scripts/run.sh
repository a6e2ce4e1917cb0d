#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# @file run.sh
# @brief The main job: set up, build, then replay the bundled pose stream over the bundled
#        Cornell box and write the stereo image sequence to out/replay/ (arguments go to xrsc).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/build.sh"
cd "$root"
exec "$root/build/host_sim/xrsc" replay "$@"
