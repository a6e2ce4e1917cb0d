# SPDX-License-Identifier: MIT
# The `xrsc` command-line conventions of issue 11, from the outside (cmake -P): --opt=value in
# every command, --version, --config FILE (the same settings as the command line; run.conf
# repeats a run exactly; bad lines named by file and line), --overwrite, --quiet.
# Inputs: -DXRSC_EXE=<path of the built program> -DOUT_DIR=<scratch folder, wiped first>.
if(NOT XRSC_EXE OR NOT OUT_DIR)
  message(FATAL_ERROR "usage: cmake -DXRSC_EXE=... -DOUT_DIR=... -P cli_conventions_test.cmake")
endif()
get_filename_component(SOURCE_DIR "${CMAKE_CURRENT_LIST_DIR}/../.." ABSOLUTE)
set(failures 0)
file(REMOVE_RECURSE "${OUT_DIR}")
file(MAKE_DIRECTORY "${OUT_DIR}")

macro(fail msg)
  message("FAIL ${msg}")
  math(EXPR failures "${failures} + 1")
endmacro()

include("${CMAKE_CURRENT_LIST_DIR}/expect_run.cmake")

# run.json's "settings" of run folder DIR into VAR, without "out" (it differs on purpose).
function(read_settings DIR VAR)
  set(s "")
  if(EXISTS "${DIR}/run.json")
    file(READ "${DIR}/run.json" json)
    string(JSON s ERROR_VARIABLE e GET "${json}" settings)
    if(e)
      set(s "bad run.json: ${e}")
    else()
      string(JSON s REMOVE "${s}" out)
    endif()
  endif()
  set(${VAR} "${s}" PARENT_SCOPE)
endfunction()

function(expect_exists NAME PATH WANT)
  set(have FALSE)
  if(EXISTS "${PATH}")
    set(have TRUE)
  endif()
  if(have STREQUAL WANT)
    message("[ ok ] ${NAME}")
  else()
    message("FAIL ${NAME}: ${PATH} exists: expected ${WANT}")
    math(EXPR f "${failures} + 1")
    set(failures ${f} PARENT_SCOPE)
  endif()
endfunction()

# --version, xrsc version, --version after a subcommand
expect_run(NAME version EXIT 0 STDOUT "^xrsc [0-9]+\\.[0-9]+\\.[0-9]+\nVulkan loader [0-9]"
           ARGS --version)
expect_run(NAME version_command EXIT 0 STDOUT "^xrsc [0-9]+\\.[0-9]+\\.[0-9]+\n" ARGS version)
expect_run(NAME version_subcommand EXIT 0 STDOUT "^xrsc [0-9]" ARGS bench --version)

# --opt=value: split for options that take a value, an error naming a flag given one
expect_run(NAME eq_flag EXIT 2 STDERR "--direct: takes no value" ARGS --direct=1)
expect_run(NAME eq_unknown EXIT 2 STDERR "--bogus: " ARGS --bogus=3)
expect_run(NAME eq_value_checked EXIT 2 STDERR "--resolution 4x4" ARGS --resolution=4x4)
expect_run(NAME eq_bench_flag EXIT 2 STDERR "--fresh: takes no value" ARGS bench --fresh=1)
expect_run(NAME eq_bench_value EXIT 2 STDERR "--resolution 4x4" ARGS bench --resolution=4x4)
expect_run(NAME eq_suite_value EXIT 2 STDERR "--frames abc" ARGS bench --suite=stability --frames=abc)
expect_run(NAME eq_metrics_flag EXIT 2 STDERR "--quiet: takes no value" ARGS metrics --quiet=1)
expect_run(NAME eq_poses EXIT 0 STDOUT "window_peak_frame"
           ARGS poses stats --fastest=1 --refresh=90 "${SOURCE_DIR}/poses/headturn.xrpose")

# A: the command line; B: the same settings from a config file (its seed overridden by the
# command line after it); C: A's run.conf. All three have the same settings, and C the same
# pixels as A (the replay repeated exactly).
set(run_args --direct --frames=2 --resolution=16x16 --spp 1 --seed=3 --write eyes,linear)
expect_run(NAME cmdline_run EXIT 0 STDOUT "frames: 2" ARGS ${run_args} --out=${OUT_DIR}/a)
file(WRITE "${OUT_DIR}/b.conf" "# the same run as a config file\n"
     "--direct\n\nframes = 2   # two frames\nresolution=16x16\n--spp 1\nseed = 99\n"
     "write = \"eyes,linear\"\n")
expect_run(NAME config_run EXIT 0 STDOUT "frames: 2"
           ARGS --config "${OUT_DIR}/b.conf" --seed 3 --out "${OUT_DIR}/b")
expect_run(NAME repeat_run EXIT 0 STDOUT "frames: 2"
           ARGS --config "${OUT_DIR}/a/run.conf" --out "${OUT_DIR}/c")
read_settings("${OUT_DIR}/a" settings_a)
read_settings("${OUT_DIR}/b" settings_b)
read_settings("${OUT_DIR}/c" settings_c)
string(JSON seed_a ERROR_VARIABLE e GET "${settings_a}" seed)
if(NOT seed_a STREQUAL "3")
  fail("settings_seed: run.json of A says seed '${seed_a}'")
endif()
if(settings_a STREQUAL "" OR NOT settings_a STREQUAL settings_b)
  fail("config_same_settings:\n  command line: ${settings_a}\n  config: ${settings_b}")
else()
  message("[ ok ] config_same_settings")
endif()
if(NOT settings_a STREQUAL settings_c)
  fail("run_conf_same_settings:\n  A: ${settings_a}\n  from A's run.conf: ${settings_c}")
else()
  message("[ ok ] run_conf_same_settings")
endif()
foreach(f frame_00000_left.pfm frame_00001_right.pfm)
  file(SHA256 "${OUT_DIR}/a/${f}" ha)
  file(SHA256 "${OUT_DIR}/c/${f}" hc)
  if(NOT ha STREQUAL hc)
    fail("run_conf_same_pixels: ${f} differs between A and its repeat")
  else()
    message("[ ok ] run_conf_same_pixels_${f}")
  endif()
endforeach()

# Bad config lines: exit 2, the error names the file, the line and the key
file(WRITE "${OUT_DIR}/bad.conf" "frames = 1\nbogus = 2\n")
expect_run(NAME config_bad_key EXIT 2 STDERR "bad\\.conf:2: --bogus: .*XRSC_ERROR_INVALID_ARGUMENT"
           ARGS --config "${OUT_DIR}/bad.conf")
file(WRITE "${OUT_DIR}/bad2.conf" "# x\ndirect = yes\n")
expect_run(NAME config_flag_value EXIT 2 STDERR "bad2\\.conf:2: --direct: "
           ARGS --config=${OUT_DIR}/bad2.conf)

# --overwrite: a folder with an earlier run is refused; with --overwrite only the program's
# files go (a stale frame of a longer run too), others stay; other files alone do not count
expect_run(NAME refuse_earlier_run EXIT 2 STDERR "--out: holds an earlier run.*--overwrite"
           ARGS --direct --frames 1 --resolution 16x16 --spp 1 --out "${OUT_DIR}/a")
file(WRITE "${OUT_DIR}/a/notes.txt" "mine")
file(WRITE "${OUT_DIR}/a/frame_00007_left.png" "stale")
expect_run(NAME overwrite EXIT 0 STDOUT "frames: 1"
           ARGS --direct --frames 1 --resolution 16x16 --spp 1 --write eyes --overwrite
                --out "${OUT_DIR}/a")
expect_exists(overwrite_keeps_other_files "${OUT_DIR}/a/notes.txt" TRUE)
expect_exists(overwrite_removes_stale_frame "${OUT_DIR}/a/frame_00007_left.png" FALSE)
expect_exists(overwrite_removes_old_pfm "${OUT_DIR}/a/frame_00001_right.pfm" FALSE)
expect_exists(overwrite_new_frame "${OUT_DIR}/a/frame_00000_left.png" TRUE)
file(WRITE "${OUT_DIR}/d/readme.txt" "not a run")
expect_run(NAME other_files_not_a_run EXIT 0 STDOUT "frames: 1"
           ARGS --direct --frames 1 --resolution 16x16 --spp 1 --write none --out "${OUT_DIR}/d")

# --quiet: nothing but errors, the OpenXR runtime's info lines included
expect_run(NAME quiet_openxr EXIT 0 STDOUT "^$" STDERR "^$"
           ARGS --frames 1 --resolution 16x16 --spp 1 --write eyes --quiet --out "${OUT_DIR}/q")
expect_exists(quiet_openxr_frame "${OUT_DIR}/q/frame_00001_left.png" TRUE)

if(failures GREATER 0)
  message(FATAL_ERROR "${failures} failed (output kept in ${OUT_DIR})")
endif()
file(REMOVE_RECURSE "${OUT_DIR}")
message("all passed")
