# SPDX-License-Identifier: MIT
# `xrsc compare A B` and `xrsc metrics` on real runs (cmake -P): two OpenXR runs of different
# methods compared (a labelled image per frame, metrics of both eyes in the table and the CSV),
# `xrsc metrics` without --first on OpenXR runs (frames start at 1) scoring both eyes and
# marking rows below a given floor (a number or a bench report), on PNG-only runs (a warning
# that they are tone-mapped), and `xrsc compare` on EXR-only runs.
# Inputs: -DXRSC_EXE=<the built program> -DOUT_DIR=<scratch folder, wiped first>.
if(NOT XRSC_EXE OR NOT OUT_DIR)
  message(FATAL_ERROR "usage: cmake -DXRSC_EXE=... -DOUT_DIR=... -P compare_test.cmake")
endif()
file(REMOVE_RECURSE ${OUT_DIR})
file(MAKE_DIRECTORY ${OUT_DIR})
set(passed 0)
set(failed 0)

macro(check NAME COND_VAR)
  if(${COND_VAR})
    math(EXPR passed "${passed} + 1")
    message("[ ok ] ${NAME}")
  else()
    math(EXPR failed "${failed} + 1")
    message("[FAIL] ${NAME}: ${ARGN}")
  endif()
endmacro()

# run(NAME args...): sets <NAME>_rc, <NAME>_out, <NAME>_err
macro(run NAME)
  execute_process(COMMAND ${XRSC_EXE} ${ARGN} RESULT_VARIABLE ${NAME}_rc
                  OUTPUT_VARIABLE ${NAME}_out ERROR_VARIABLE ${NAME}_err)
endmacro()

# Two small runs through OpenXR under the validation layer (frames 1..3), linear and PNG.
set(common --resolution 64x64 --frames 3 --validation --quiet)
run(a replay ${common} --method spp --write eyes,linear --out ${OUT_DIR}/a)
run(b replay ${common} --method samplecache --write eyes,linear --out ${OUT_DIR}/b)
foreach(r a b)
  set(ok FALSE)
  if(${r}_rc EQUAL 0 AND NOT ${r}_err MATCHES "validation|VUID")
    set(ok TRUE)
  endif()
  check("run ${r}" ok "exit ${${r}_rc}: ${${r}_err}")
endforeach()

# compare: 3 images, a CSV of 6 rows (3 frames x 2 eyes), both eyes in the table
run(c compare ${OUT_DIR}/a ${OUT_DIR}/b --out ${OUT_DIR}/cmp)
set(ok FALSE)
if(c_rc EQUAL 0 AND c_out MATCHES "mean  left" AND c_out MATCHES "mean right"
   AND c_out MATCHES "\n +1 +left" AND c_out MATCHES "\n +3 +right")
  set(ok TRUE)
endif()
check("compare: table of both eyes from frame 1" ok "exit ${c_rc}\n${c_out}\n${c_err}")
set(ok TRUE)
foreach(f 1 2 3)
  if(NOT EXISTS ${OUT_DIR}/cmp/compare_0000${f}.png)
    set(ok FALSE)
  endif()
endforeach()
if(EXISTS ${OUT_DIR}/cmp/compare_00000.png OR EXISTS ${OUT_DIR}/cmp/compare_00004.png)
  set(ok FALSE)
endif()
check("compare: one image per frame" ok)
file(STRINGS ${OUT_DIR}/cmp/compare.csv csv)
list(LENGTH csv n)
list(GET csv 0 header)
set(ok FALSE)
if(n EQUAL 7 AND header STREQUAL "frame,eye,relmse,rmse,mse,psnr_db,ssim")
  list(GET csv 2 row)
  # different methods at 64x64 and 1-2 spp: not identical (relMSE > 0, SSIM < 1)
  if(row MATCHES "^1,right,([0-9.e+-]+),.*,([0-9.]+)$" AND CMAKE_MATCH_1 GREATER 0
     AND CMAKE_MATCH_2 LESS 1)
    set(ok TRUE)
  endif()
endif()
check("compare: CSV rows for both eyes" ok "${csv}")
# A run against itself: relMSE 0 and SSIM 1 (the check can fail).
run(same compare ${OUT_DIR}/a ${OUT_DIR}/a --out ${OUT_DIR}/same --quiet)
set(ok FALSE)
if(same_rc EQUAL 0 AND same_out MATCHES "mean  left +0 +0 +inf +1\\.0+")
  set(ok TRUE)
endif()
check("compare: a run against itself is equal" ok "${same_out}${same_err}")

# metrics without --first: starts at the OpenXR run's frame 1, both eyes; --floor marks rows
run(m metrics --ref ${OUT_DIR}/a --test ${OUT_DIR}/b --floor 1e9)
set(ok FALSE)
if(m_rc EQUAL 0 AND m_out MATCHES "\n +1 +left" AND m_out MATCHES "\n +1 +right"
   AND m_out MATCHES "below floor" AND m_out MATCHES "mean right")
  set(ok TRUE)
endif()
check("metrics: OpenXR run without --first, both eyes, floor" ok "exit ${m_rc}\n${m_out}\n${m_err}")
run(m0 metrics --ref ${OUT_DIR}/a --test ${OUT_DIR}/b --floor 1e-12)
set(ok FALSE)
if(m0_rc EQUAL 0 AND NOT m0_out MATCHES "below floor")
  set(ok TRUE)
endif()
check("metrics: no row below a tiny floor" ok "${m0_out}")
# the floor from a saved `xrsc bench --ref-floor` report: half its two-reference relMSE
file(WRITE ${OUT_DIR}/bench_report.txt
     "reference floor relMSE ≈ 4e+09 (two 64-spp references of frame 3, independent seeds)\n")
run(mf metrics --ref ${OUT_DIR}/a --test ${OUT_DIR}/b --floor ${OUT_DIR}/bench_report.txt)
set(ok FALSE)
if(mf_rc EQUAL 0 AND mf_out MATCHES "below floor" AND mf_out MATCHES "floor: relMSE 2e\\+09")
  set(ok TRUE)
endif()
check("metrics: floor from a bench report" ok "exit ${mf_rc}\n${mf_out}\n${mf_err}")

# PNG-only runs: scored with a warning
run(pa replay ${common} --method spp --write eyes --out ${OUT_DIR}/pa)
run(pb replay ${common} --method samplecache --write eyes --out ${OUT_DIR}/pb)
run(p metrics --ref ${OUT_DIR}/pa --test ${OUT_DIR}/pb)
set(ok FALSE)
if(pa_rc EQUAL 0 AND pb_rc EQUAL 0 AND p_rc EQUAL 0 AND p_err MATCHES "warning: .*tone-mapped"
   AND p_out MATCHES "mean right")
  set(ok TRUE)
endif()
check("metrics: PNG runs with a warning" ok "exit ${p_rc}\n${p_out}\n${p_err}")
# EXR-only runs (--write exr): linear, no warning
run(xa replay ${common} --method spp --write exr --out ${OUT_DIR}/xa)
run(xb replay ${common} --method samplecache --write exr --out ${OUT_DIR}/xb)
run(x compare ${OUT_DIR}/xa ${OUT_DIR}/xb --out ${OUT_DIR}/xcmp --quiet)
set(ok FALSE)
if(xa_rc EQUAL 0 AND xb_rc EQUAL 0 AND x_rc EQUAL 0 AND NOT x_err MATCHES "warning"
   AND x_out MATCHES "mean right" AND EXISTS ${OUT_DIR}/xcmp/compare_00003.png)
  set(ok TRUE)
endif()
check("compare: EXR runs" ok "exit ${xa_rc} ${xb_rc} ${x_rc}\n${x_out}\n${x_err}")
# a folder without frames is an error naming it
run(e metrics --ref ${OUT_DIR}/cmp --test ${OUT_DIR}/b)
set(ok FALSE)
if(e_rc EQUAL 1 AND e_err MATCHES "cmp")
  set(ok TRUE)
endif()
check("metrics: a folder without frames" ok "exit ${e_rc}: ${e_err}")

message("${passed} passed, ${failed} failed")
if(failed)
  message(FATAL_ERROR "${failed} failed")
endif()
