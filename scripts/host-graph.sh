#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# @file host-graph.sh
# @brief Draws host_sim's library graph from CMake's own target graph (`cmake --graphviz`):
#        host_sim/layers.svg, shown in host_sim/README.md. Needs a configured build folder and
#        graphviz's `dot` (apt-get install graphviz); run it again after changing a
#        target_link_libraries line of host_sim and commit the picture.
# Usage: scripts/host-graph.sh [BUILD_DIR]   (default: build)
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
build=$(cd "${1:-$root/build}" && pwd)
command -v dot > /dev/null || { echo "host-graph.sh: needs graphviz's dot (apt-get install graphviz)"; exit 1; }
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
# CMake reads its graph options from the build folder; keep only the host's libraries, the
# program and the plugin libraries they link directly (no tests, tools, fuzzers, system libs).
opts=$build/CMakeGraphVizOptions.cmake
cat > "$opts" <<'OPTS'
set(GRAPHVIZ_GRAPH_NAME "host_sim")
set(GRAPHVIZ_EXTERNAL_LIBS FALSE)
set(GRAPHVIZ_GENERATE_PER_TARGET FALSE)
set(GRAPHVIZ_GENERATE_DEPENDERS FALSE)
set(GRAPHVIZ_INTERFACE_LIBS FALSE)
set(GRAPHVIZ_IGNORE_TARGETS "^test_" "^fuzz_" "^xrsc_testing$" "^xrsc_make_" "^xrsc_shaders"
    "^xrsc_(scene|gpu|methods|stereo|temporal|core)$" "^bench_" "^t_")
OPTS
(cd "$build" && cmake --graphviz="$tmp/graph.dot" . > /dev/null)
rm -f "$opts"
dot -Tsvg -Grankdir=BT "$tmp/graph.dot" -o "$root/host_sim/layers.svg"
echo "wrote host_sim/layers.svg"
