# SPDX-License-Identifier: MIT
# Issue 18 from the outside (cmake -P): --viewpoint errors name the option (exit 2), the hint
# IDs a 7 mm model gets without --frame, none with it, and the summary's load line.
# Inputs: -DXRSC_EXE=<the program> -DOUT_DIR=<scratch folder, wiped first> -DSHARED_DIR=<shared/>.
if(NOT XRSC_EXE OR NOT OUT_DIR OR NOT SHARED_DIR)
  message(FATAL_ERROR "usage: cmake -DXRSC_EXE=... -DOUT_DIR=... -DSHARED_DIR=... -P view_cli_test.cmake")
endif()
set(failures 0)
include("${CMAKE_CURRENT_LIST_DIR}/expect_run.cmake")
file(REMOVE_RECURSE "${OUT_DIR}")

expect_run(NAME viewpoint_two_numbers EXIT 2 STDERR "--viewpoint 1,2: " ARGS --viewpoint 1,2)
expect_run(NAME viewpoint_bad_camera EXIT 2 STDERR "--viewpoint camera:x: " ARGS --viewpoint camera:x)
expect_run(NAME viewpoint_bad_yaw EXIT 2 STDERR "--viewpoint 0,1,2:up: " ARGS --viewpoint 0,1,2:up)
expect_run(NAME viewpoint_and_frame EXIT 2 STDERR "--viewpoint: .*--frame"
           ARGS --frame --viewpoint inside)

set(tiny "${SHARED_DIR}/scenes/khronos/MetalRoughSpheresNoTextures/glTF-Binary/MetalRoughSpheresNoTextures.glb")
set(common --direct --scene "${tiny}" --frames 1 --resolution 16x16 --method primary)
expect_run(NAME tiny_default_hints EXIT 0
           STDERR "\\[narrower-than-ipd\\].*\\[(view-misses-scene|scene-too-small)\\].*--frame"
           ARGS ${common} --out "${OUT_DIR}/tiny")
expect_run(NAME tiny_frame_no_hint EXIT 0
           STDOUT "load: scene [0-9.]+ s .*, [0-9]+ triangles, [0-9]+ materials, [0-9]+ textures, [0-9]+ lights.*peak memory"
           NOT_STDERR "view-misses-scene|scene-too-small|inside-geometry"
           ARGS ${common} --frame --out "${OUT_DIR}/tinyframe")
expect_run(NAME viewpoint_missing_camera EXIT 1 STDERR "--viewpoint: camera 3 does not exist"
           ARGS ${common} --viewpoint camera:3 --out "${OUT_DIR}/nocam")

math(EXPR passed "7 - ${failures}")
message("${passed} passed, ${failures} failed")
if(failures GREATER 0)
  message(FATAL_ERROR "output kept in ${OUT_DIR}")
endif()
file(REMOVE_RECURSE "${OUT_DIR}")
