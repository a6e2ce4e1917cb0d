# SPDX-License-Identifier: MIT
# The `xrsc` program from the outside (cmake -P): --help, a bad flag, a tiny real run.
# Inputs: -DXRSC_EXE=<path of the built program> -DOUT_DIR=<scratch folder, wiped first>.
if(NOT XRSC_EXE OR NOT OUT_DIR)
  message(FATAL_ERROR "usage: cmake -DXRSC_EXE=... -DOUT_DIR=... -P cli_test.cmake")
endif()
set(failures 0)

include("${CMAKE_CURRENT_LIST_DIR}/expect_run.cmake")

function(expect_file NAME PATH)
  if(EXISTS "${PATH}" AND NOT IS_DIRECTORY "${PATH}")
    message("[ ok ] ${NAME}")
  else()
    message("FAIL ${NAME}: ${PATH} missing")
    math(EXPR f "${failures} + 1")
    set(failures ${f} PARENT_SCOPE)
  endif()
endfunction()

expect_run(NAME help EXIT 0 STDOUT "^usage: xrsc .*--resolution WxH" ARGS --help)
expect_run(NAME help_short EXIT 0 STDOUT "^usage: xrsc" ARGS -h)
expect_run(NAME unknown_flag EXIT 2 STDERR "--bogus: unknown option" ARGS --bogus)
expect_run(NAME unknown_flag_with_value EXIT 2 STDERR "unknown option" ARGS --bogus 3)
expect_run(NAME missing_value EXIT 2 STDERR "needs a value" ARGS --frames)
expect_run(NAME bad_resolution EXIT 2 STDERR "--resolution 4x4" ARGS --resolution 4x4)
expect_run(NAME bad_method EXIT 2 ARGS --method nope)
expect_run(NAME bad_write_list EXIT 2 ARGS --write eyes,gif)

file(REMOVE_RECURSE "${OUT_DIR}")
expect_run(NAME missing_poses EXIT 1 STDERR "XRSC_ERROR_IO"
           ARGS --poses "${OUT_DIR}/none.xrpose" --frames 1 --out "${OUT_DIR}/x" --quiet)

expect_run(NAME tiny_run EXIT 0 STDOUT "frames: 2"
           ARGS --direct --frames 2 --resolution 16x16 --spp 1 --write eyes,sbs,linear
                --out "${OUT_DIR}/run")
foreach(f frame_00000_left.png frame_00000_right.png frame_00001_sbs.png frame_00001_right.pfm
          frames.csv)
  expect_file(tiny_run_${f} "${OUT_DIR}/run/${f}")
endforeach()
if(EXISTS "${OUT_DIR}/run/frames.csv")
  file(STRINGS "${OUT_DIR}/run/frames.csv" lines)
  list(LENGTH lines n)
  if(n EQUAL 3)
    message("[ ok ] tiny_run_csv_rows")
  else()
    message("FAIL tiny_run_csv_rows: ${n} lines, expected a header and 2 rows")
    math(EXPR failures "${failures} + 1")
  endif()
endif()

# The default path: OpenXR on this build's host_sim runtime (frames 1..2: a session's first
# frame is not shown), the runtime writing the frames.
expect_run(NAME tiny_xr_run EXIT 0 STDOUT "frames: 2"
           ARGS --frames 2 --resolution 16x16 --spp 1 --write eyes,linear
                --out "${OUT_DIR}/xrrun")
foreach(f frame_00001_left.png frame_00002_right.png frame_00002_left.pfm frames.csv)
  expect_file(tiny_xr_run_${f} "${OUT_DIR}/xrrun/${f}")
endforeach()
# --start and --ipd reach the runtime (XRSC_RT_START_S, XRSC_RT_IPD_MM): its frames.csv has
# frame 0 at stream time 0.5 s.
expect_run(NAME xr_start_ipd EXIT 0 STDOUT "frames: 1"
           ARGS --frames 1 --start 0.5 --ipd 70 --resolution 16x16 --spp 1 --write eyes
                --out "${OUT_DIR}/xrstart")
if(EXISTS "${OUT_DIR}/xrstart/frames.csv")
  file(STRINGS "${OUT_DIR}/xrstart/frames.csv" start_rows)
  list(GET start_rows 1 row0)
  if(row0 MATCHES "^0,[0-9]+,500000000,")
    message("[ ok ] xr_start_stream_time")
  else()
    message("FAIL xr_start_stream_time: frame 0 row '${row0}'")
    math(EXPR failures "${failures} + 1")
  endif()
else()
  message("FAIL xr_start_stream_time: ${OUT_DIR}/xrstart/frames.csv missing")
  math(EXPR failures "${failures} + 1")
endif()
expect_run(NAME xr_bad_ipd EXIT 2 STDERR "--ipd" ARGS --ipd 300 --frames 1 --quiet)
# --device means the same on both paths: a selector that matches no device ends in
# XRSC_ERROR_DEVICE_NOT_FOUND naming it, through OpenXR too (the plugin checks it against the
# devices of the instance made through the runtime before asking the runtime, whose own
# answer, XR_ERROR_RUNTIME_FAILURE, would not say what was wrong).
expect_run(NAME direct_device_not_found EXIT 1
           STDERR "no Vulkan device matches \"nosuch\".*XRSC_ERROR_DEVICE_NOT_FOUND"
           ARGS --direct --device nosuch --frames 1 --resolution 16x16 --write none --quiet
                --out "${OUT_DIR}/nodevice_direct")
expect_run(NAME xr_device_not_found EXIT 1
           STDERR "no Vulkan device matches \"nosuch\".*XRSC_ERROR_DEVICE_NOT_FOUND"
           NOT_STDERR "XR_ERROR_RUNTIME_FAILURE|XRSC_ERROR_VULKAN"
           ARGS --device nosuch --frames 1 --resolution 16x16 --write none --quiet
                --out "${OUT_DIR}/nodevice_xr")

# Issue 11 item 6: headset profiles (data: host_sim/headsets.txt) and --write exr.
expect_run(NAME headset_list EXIT 0 STDOUT "quest3 .*2064x2208.*index .*1440x1600.*vision-pro"
           ARGS --headset list)
expect_run(NAME headset_unknown EXIT 2 STDERR "unknown headset 'quest9'.*quest3.*index"
           ARGS --headset quest9 --frames 1)
file(WRITE "${OUT_DIR}/broken-headsets.txt" "[x]\ntitle = X\nresolution = 64x\n")
expect_run(NAME headsets_file_broken EXIT 2
           STDERR "broken-headsets.txt:3: resolution: .*XRSC_ERROR_BAD_NUMBER"
           ARGS --headsets "${OUT_DIR}/broken-headsets.txt" --headset x --frames 1)
expect_run(NAME headset_exr_run EXIT 0 STDOUT "frames: 1"
           ARGS --direct --headset index --resolution 16x16 --frames 1 --spp 1 --write exr
                --out "${OUT_DIR}/exrrun")
expect_file(headset_exr_run_left "${OUT_DIR}/exrrun/frame_00000_left.exr")
expect_file(headset_exr_run_right "${OUT_DIR}/exrrun/frame_00000_right.exr")
# --video without ffmpeg (XRSC_FFMPEG names a missing one): a warning, the run succeeds.
set(ENV{XRSC_FFMPEG} "${OUT_DIR}/no-such-ffmpeg")
expect_run(NAME video_without_ffmpeg EXIT 0 STDERR "ffmpeg is not installed"
           ARGS --direct --frames 1 --resolution 16x16 --spp 1 --write none
                --video "${OUT_DIR}/v.mp4" --out "${OUT_DIR}/vid")
unset(ENV{XRSC_FFMPEG})

# --fov scene through OpenXR: the glTF camera's FOV reaches the runtime (XRSC_RT_FOV_DEG), so
# its frame 1 equals the direct path's pixel for pixel (`primary`: no noise); with the
# headset's FOV it does not (the check can fail).
foreach(run direct xr xrheadset)
  set(args --method primary --frames 2 --resolution 16x12 --write linear --quiet
           --out "${OUT_DIR}/fov_${run}")
  if(run STREQUAL "direct")
    list(APPEND args --direct --fov scene)
  elseif(run STREQUAL "xr")
    list(APPEND args --fov scene)
  endif()
  expect_run(NAME fov_scene_${run} EXIT 0 ARGS ${args})
endforeach()
foreach(eye left right)
  set(f frame_00001_${eye}.pfm)
  if(EXISTS "${OUT_DIR}/fov_direct/${f}" AND EXISTS "${OUT_DIR}/fov_xr/${f}" AND
     EXISTS "${OUT_DIR}/fov_xrheadset/${f}")
    file(SHA256 "${OUT_DIR}/fov_direct/${f}" h_direct)
    file(SHA256 "${OUT_DIR}/fov_xr/${f}" h_xr)
    file(SHA256 "${OUT_DIR}/fov_xrheadset/${f}" h_headset)
    if(h_direct STREQUAL h_xr AND NOT h_headset STREQUAL h_xr)
      message("[ ok ] fov_scene_same_frames_${eye}")
    else()
      message("FAIL fov_scene_same_frames_${eye}: direct ${h_direct}, OpenXR ${h_xr}, "
              "OpenXR with the headset's FOV ${h_headset}")
      math(EXPR failures "${failures} + 1")
    endif()
  else()
    message("FAIL fov_scene_same_frames_${eye}: frames missing")
    math(EXPR failures "${failures} + 1")
  endif()
endforeach()

if(failures GREATER 0)
  message(FATAL_ERROR "${failures} failed (output kept in ${OUT_DIR})")
endif()
file(REMOVE_RECURSE "${OUT_DIR}")
message("all passed")
