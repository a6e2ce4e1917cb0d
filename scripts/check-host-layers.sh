#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# @file check-host-layers.sh
# @brief Checks that no host_sim library includes a header of a library above it: every
#        `#include "X"` in host_sim/<folder>/ that names a header of another host_sim folder must
#        name one of the folders that folder may include (host_sim/README.md). Plugin headers
#        (plugin/include, plugin/src/util) are below every host folder and always allowed.
#
# Usage: scripts/check-host-layers.sh [HOST_SIM_DIR]   (default: host_sim next to this script)
# Prints each violation as FILE:LINE: includes HEADER (of FOLDER; FOLDER may include: ...) and
# ends with "N passed, N failed" (one check per folder); exit status 1 on any violation.
set -u
dir=${1:-$(cd "$(dirname "$0")/.." && pwd)/host_sim}

# The layers, bottom first, and what each may include (besides itself).
declare -A allowed=(
  [io]=""
  [pose]="io"
  [replay]="io pose"
  [bench]="io pose replay"
  [app]="io pose replay bench"
  [runtime]="io pose"
)
folders="io pose replay bench app runtime"

# Which folder owns each header name.
declare -A owner=()
for f in $folders; do
  [ -d "$dir/$f" ] || { echo "missing folder $dir/$f"; echo "0 passed, 1 failed"; exit 1; }
  for h in "$dir/$f"/*.h; do
    [ -e "$h" ] && owner[${h##*/}]=$f
  done
done

passed=0 failed=0
for f in $folders; do
  bad=0
  for src in "$dir/$f"/*.c "$dir/$f"/*.h; do
    [ -e "$src" ] || continue
    while IFS=: read -r line inc; do
      h=${inc##*/}
      o=${owner[$h]:-}
      [ -z "$o" ] || [ "$o" = "$f" ] && continue
      case " ${allowed[$f]} " in
        *" $o "*) ;;
        *) echo "${src#"$dir"/}:$line: includes $inc (of $o; $f may include: ${allowed[$f]:-nothing else})"
           bad=1 ;;
      esac
    done < <(grep -n '^[[:space:]]*#[[:space:]]*include[[:space:]]*"' "$src" |
             sed -E 's/^([0-9]+):.*"([^"]+)".*/\1:\2/')
  done
  if [ $bad = 0 ]; then passed=$((passed + 1)); else failed=$((failed + 1)); fi
done
echo "$passed passed, $failed failed"
[ $failed = 0 ]
