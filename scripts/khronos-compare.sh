#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# @file khronos-compare.sh
# @brief Renders every Khronos sample model in ../shared/scenes/khronos/*/ and puts each render
#        beside the screenshot the model ships, one side-by-side PNG per model.
#
# Usage: scripts/khronos-compare.sh [OUT_DIR]        (default build/khronos-compare)
# For each folder with a .gltf or .glb (glTF-Binary/ preferred, then glTF/): `xrsc replay
# --direct` over poses/still.xrpose, from the model's first camera (--viewpoint camera:0
# --fov scene, the eye's width made to the camera's aspectRatio so that nothing is squeezed)
# when it has one, else --frame; the left eye of the last frame is
# OUT_DIR/MODEL/frame_NNNNN_left.png and OUT_DIR/MODEL-side-by-side.png is it beside
# screenshot/screenshot.{png,jpg} (else the first image there; a GIF's first frame), both
# scaled to one height by the project's own xrsc_side_by_side (Debian's stb_image; no
# ImageMagick needed). A folder without a glTF file (LightsPunctualLamp ships screenshots only)
# is listed as such. A model that is refused is listed with xrsc's exit status and its error
# (OUT_DIR/MODEL.log). Prints one line per model; exits 1 when any model was refused.
# Environment (defaults in brackets):
#   KHRONOS_DIR     the models' folder                       [<repo>/../shared/scenes/khronos]
#   KHRONOS_BUILD   the build folder                         [<repo>/build]
#   KHRONOS_METHOD  --method                                 [spp]
#   KHRONOS_SPP     --spp per frame; KHRONOS_FRAMES frames    [16; 4] (accumulated: spp x frames)
#   KHRONOS_SIZE    --resolution per eye                     [256x256]
#   KHRONOS_HEIGHT  height of the side-by-side images (px)    [360]
#   KHRONOS_ARGS    more xrsc options for every model (e.g. "--sky")  []
set -uo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
models=${KHRONOS_DIR:-$root/../shared/scenes/khronos}
build=${KHRONOS_BUILD:-$root/build}
out=${1:-$build/khronos-compare}
xrsc=$build/host_sim/xrsc
sbs=$build/scenes/xrsc_side_by_side
method=${KHRONOS_METHOD:-spp}
spp=${KHRONOS_SPP:-16}
frames=${KHRONOS_FRAMES:-4}
size=${KHRONOS_SIZE:-256x256}
height=${KHRONOS_HEIGHT:-360}
read -r -a extra <<<"${KHRONOS_ARGS:-}"

for tool in "$xrsc" "$sbs"; do
    if [ ! -x "$tool" ]; then
        echo "khronos-compare: $tool is missing: build first (scripts/build.sh)" >&2
        exit 2
    fi
done
mkdir -p "$out" || exit 2

# The model's glTF file: glTF-Binary first, then glTF, then any.
model_file() { # DIR
    local f
    for f in "$1"/glTF-Binary/*.glb "$1"/glTF/*.gltf "$1"/*/*.gl[bt]* "$1"/*.gl[bt]*; do
        [ -f "$f" ] && { echo "$f"; return 0; }
    done
    return 1
}

# The screenshot: screenshot.png/.jpg, else the first image in screenshot/.
screenshot() { # DIR
    local f
    for f in "$1"/screenshot/screenshot.png "$1"/screenshot/screenshot.jpg \
        "$1"/screenshot/*.png "$1"/screenshot/*.jpg "$1"/screenshot/*.gif; do
        [ -f "$f" ] && { echo "$f"; return 0; }
    done
    return 1
}

# Whether the glTF file has a camera (a "cameras" array in its JSON or GLB JSON chunk).
has_camera() { # FILE
    LC_ALL=C grep -aq '"cameras"[[:space:]]*:[[:space:]]*\[[[:space:]]*{' "$1"
}

status=0
for dir in "$models"/*/; do
    dir=${dir%/}
    name=$(basename "$dir")
    if ! file=$(model_file "$dir"); then
        echo "$name: no glTF file (screenshots only)"
        continue
    fi
    view=(--frame)
    res=$size
    if has_camera "$file"; then
        view=(--viewpoint camera:0 --fov scene)
        aspect=$(LC_ALL=C grep -ao '"aspectRatio"[[:space:]]*:[[:space:]]*[0-9.]*' "$file" |
            head -n 1 | sed 's/.*://; s/[[:space:]]//g')
        [ -n "$aspect" ] && res=$(awk -v s="$size" -v a="$aspect" \
            'BEGIN { split(s, p, "x"); printf "%dx%d", p[2] * a + 0.5, p[2] }')
    fi
    run=$out/$name
    if ! "$xrsc" replay --direct --quiet --overwrite --scene "$file" --poses "$root/poses/still.xrpose" \
        --frames "$frames" --method "$method" --spp "$spp" --resolution "$res" --write eyes \
        --out "$run" "${view[@]}" "${extra[@]}" >"$out/$name.log" 2>&1; then
        echo "$name: REFUSED (exit $?): $(grep -m1 -i error "$out/$name.log")"
        status=1
        continue
    fi
    left=$(ls "$run"/frame_*_left.png 2>/dev/null | tail -n 1)
    shot=$(screenshot "$dir") || shot=
    if [ -z "$left" ]; then
        echo "$name: rendered, but no left-eye PNG in $run"
        status=1
    elif [ -z "$shot" ]; then
        echo "$name: $left (no screenshot to compare with)"
    elif "$sbs" "$out/$name-side-by-side.png" "$height" "$left" "$shot"; then
        echo "$name: $out/$name-side-by-side.png (${view[*]}; left: xrsc, right: $(basename "$shot"))"
    else
        echo "$name: $left (the side-by-side image failed)"
        status=1
    fi
done
exit $status
