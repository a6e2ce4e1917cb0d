# SPDX-License-Identifier: MIT
# Issue 21 item 2 from the outside (cmake -P): `xrsc scene info` on the Khronos Fox (3 clips)
# and CesiumMan (1 clip), text and --json; --animation of replay (both paths) and bench: an
# unknown clip is XRSC_ERROR_ANIMATION_UNKNOWN naming the file's clips; the chosen clip plays
# at the display time, so the direct and the OpenXR path write the same frames, and with
# `none` nothing moves.
# Inputs: -DXRSC_EXE=<the program> -DOUT_DIR=<scratch folder, wiped first> -DSHARED_DIR=<shared/>.
if(NOT XRSC_EXE OR NOT OUT_DIR OR NOT SHARED_DIR)
  message(FATAL_ERROR "usage: cmake -DXRSC_EXE=... -DOUT_DIR=... -DSHARED_DIR=... -P scene_cli_test.cmake")
endif()
get_filename_component(SOURCE_DIR "${CMAKE_CURRENT_LIST_DIR}/../.." ABSOLUTE)
set(failures 0)
file(REMOVE_RECURSE "${OUT_DIR}")
file(MAKE_DIRECTORY "${OUT_DIR}")
include("${CMAKE_CURRENT_LIST_DIR}/expect_run.cmake")

set(fox "${SHARED_DIR}/scenes/khronos/Fox/glTF-Binary/Fox.glb")
set(man "${SHARED_DIR}/scenes/khronos/CesiumMan/glTF-Binary/CesiumMan.glb")

# ---- xrsc scene info ----
expect_run(NAME info_fox EXIT 0
           STDOUT "triangles: 576 .*nodes: 26  meshes: 1  skins: 1 .*clips: 3 \\(plays: 0\\)\n  \\*  0  Survey +3\\.41[0-9] s +21 channels\n     1  Walk +0\\.70[0-9] s +21 channels\n     2  Run +1\\.15[0-9] s +21 channels"
           ARGS scene info "${fox}")
expect_run(NAME info_fox_animation_run EXIT 0 STDOUT "clips: 3 \\(plays: 2\\).*\n  \\*  2  Run"
           ARGS scene info --animation Run "${fox}")
expect_run(NAME info_fox_json EXIT 0
           STDOUT "^{\"file\": .*\"triangles\": 576, .*\"skins\": 1, .*\"clip_playing\": 0, \"clips\": \\[{\"index\": 0, \"name\": \"Survey\", \"duration_s\": 3\\.41[0-9]*, \"channels\": 21}, {\"index\": 1, \"name\": \"Walk\", .*{\"index\": 2, \"name\": \"Run\", .*}\\]}\n$"
           ARGS scene info --json "${fox}")
expect_run(NAME info_cesiumman EXIT 0
           STDOUT "triangles: 4672 .*materials: 1  textures: 1 \\(images 1\\).*nodes: 22  meshes: 1  skins: 1  morph targets: 0.*clips: 1 \\(plays: 0\\)\n  \\*  0  \\(unnamed\\) +2\\.0[0-9]* s +57 channels"
           ARGS scene info "${man}")
expect_run(NAME info_cesiumman_none EXIT 0 STDOUT "clips: 1 \\(plays: none\\)"
           ARGS scene info --animation=none "${man}")
expect_run(NAME info_unknown_clip EXIT 1
           STDERR "Fox.glb: animation: no clip 'Jump'.*0 \"Survey\".*1 \"Walk\".*2 \"Run\".*XRSC_ERROR_ANIMATION_UNKNOWN"
           ARGS scene info --animation Jump "${fox}")
expect_run(NAME info_index_past_end EXIT 1 STDERR "XRSC_ERROR_ANIMATION_UNKNOWN"
           ARGS scene info --animation 3 "${fox}")
expect_run(NAME info_no_subcommand EXIT 2 STDERR "expected the subcommand info" ARGS scene)
expect_run(NAME info_no_file EXIT 2 STDERR "expected one FILE" ARGS scene info)
expect_run(NAME info_bad_option EXIT 2 STDERR "--bogus: unknown option" ARGS scene info --bogus x)
expect_run(NAME info_missing_file EXIT 1 STDERR "XRSC_ERROR_IO"
           ARGS scene info "${OUT_DIR}/none.glb")
expect_run(NAME info_help EXIT 0 STDOUT "^usage: xrsc scene info" ARGS scene --help)

# ---- --animation of replay and bench ----
set(scene "${SOURCE_DIR}/scenes/disocclusion.gltf") # one clip: the box slides along x
set(still "${SOURCE_DIR}/poses/still.xrpose")
expect_run(NAME replay_unknown_clip EXIT 1 STDERR "no clip 'walk'.*XRSC_ERROR_ANIMATION_UNKNOWN"
           ARGS --direct --scene "${scene}" --poses "${still}" --animation walk --frames 1
                --resolution 16x16 --write none --out "${OUT_DIR}/unknown" --quiet)
expect_run(NAME replay_empty_animation EXIT 2 STDERR "--animation" ARGS --animation= --frames 1)
expect_run(NAME bench_unknown_clip EXIT 1 STDERR "no clip '7'.*XRSC_ERROR_ANIMATION_UNKNOWN"
           ARGS bench --scene "${scene}" --poses "${still}" --animation 7 --frames 2 --warmup 0
                --resolution 16x16 --settings primary --out "${OUT_DIR}/bench" --quiet --no-plots)
# 20 frames (0.21 s: the box moves 0.5 m): `primary` has no noise, so frames compare exactly.
foreach(run direct xr)
  foreach(anim first none)
    set(args --scene "${scene}" --poses "${still}" --method primary --frames 20
             --resolution 16x12 --write linear --animation ${anim} --quiet
             --out "${OUT_DIR}/${run}_${anim}")
    if(run STREQUAL "direct")
      list(APPEND args --direct)
    endif()
    expect_run(NAME replay_${run}_${anim} EXIT 0 ARGS ${args})
  endforeach()
endforeach()
set(hashes "")
foreach(d direct_first xr_first direct_none xr_none)
  foreach(k 00001 00019)
    set(f "${OUT_DIR}/${d}/frame_${k}_left.pfm")
    if(EXISTS "${f}")
      file(SHA256 "${f}" h_${d}_${k})
    else()
      set(h_${d}_${k} "missing ${d} ${k}")
    endif()
  endforeach()
endforeach()
if(h_direct_first_00019 STREQUAL h_xr_first_00019 AND
   NOT h_direct_first_00019 STREQUAL h_direct_first_00001)
  message("[ ok ] clip_plays_same_on_both_paths")
else()
  message("FAIL clip_plays_same_on_both_paths: frame 19 direct ${h_direct_first_00019}, "
          "OpenXR ${h_xr_first_00019}, frame 1 direct ${h_direct_first_00001}")
  math(EXPR failures "${failures} + 1")
endif()
if(h_direct_none_00019 STREQUAL h_direct_none_00001 AND
   h_xr_none_00019 STREQUAL h_direct_none_00001)
  message("[ ok ] animation_none_stands_still")
else()
  message("FAIL animation_none_stands_still: frame 1 ${h_direct_none_00001}, frame 19 direct "
          "${h_direct_none_00019}, OpenXR ${h_xr_none_00019}")
  math(EXPR failures "${failures} + 1")
endif()
file(STRINGS "${OUT_DIR}/direct_none/run.conf" conf REGEX "^animation = none$")
if(conf)
  message("[ ok ] run_conf_records_animation")
else()
  message("FAIL run_conf_records_animation: no 'animation = none' in run.conf")
  math(EXPR failures "${failures} + 1")
endif()

if(failures GREATER 0)
  message(FATAL_ERROR "${failures} failed (output kept in ${OUT_DIR})")
endif()
file(REMOVE_RECURSE "${OUT_DIR}")
message("all passed")
