# SPDX-License-Identifier: MIT
# Issue 19 item 5 (cmake -P): `xrsc metrics --stereo` on a replay written with --write exr
# reproduces `xrsc bench`'s temporal and stereo figures for the same frames (2 x 48 x 48,
# 4 frames, spp 1 and samplecache without a blend): per frame the valid pixel counts exactly,
# the values and the summary's means to the bench's printed precision (6 significant digits:
# relative 1e-5); the OpenXR path writes views.csv too (frames 1..3) and its figures agree
# with the bench's within 1e-4 (the runtime's pose arithmetic rounds floats differently);
# a folder holding only a views.csv counts as an earlier run. Issue 19 item 1: the bench's
# setting `default` and a replay given no method or blend render the same frames (the
# same figures to that precision; a bench `samplecache` has no blend, the replay's does).
# Inputs: -DXRSC_EXE=<the built program> -DOUT_DIR=<scratch folder, wiped first>.
if(NOT XRSC_EXE OR NOT OUT_DIR)
  message(FATAL_ERROR "usage: cmake -DXRSC_EXE=... -DOUT_DIR=... -P metrics_stereo_test.cmake")
endif()
file(REMOVE_RECURSE ${OUT_DIR})
file(MAKE_DIRECTORY ${OUT_DIR})
set(passed 0)
set(failed 0)
# The bench writes %.6g: a value it prints is within 5e-6 relative of the exact one, and its
# summary's mean of printed values within 1e-5.
set(BENCH_REL_TOL 100000) # 1 / 1e-5
set(XR_REL_TOL 10000)     # 1 / 1e-4

macro(check NAME COND_VAR)
  if(${COND_VAR})
    math(EXPR passed "${passed} + 1")
    message("[ ok ] ${NAME}")
  else()
    math(EXPR failed "${failed} + 1")
    message("[FAIL] ${NAME}: ${ARGN}")
  endif()
endmacro()

macro(run NAME)
  execute_process(COMMAND ${XRSC_EXE} ${ARGN} RESULT_VARIABLE ${NAME}_rc
                  OUTPUT_VARIABLE ${NAME}_out ERROR_VARIABLE ${NAME}_err)
  set(ok FALSE)
  if(${NAME}_rc EQUAL 0 AND NOT ${NAME}_err MATCHES "validation|VUID")
    set(ok TRUE)
  endif()
  check("run ${NAME}" ok "exit ${${NAME}_rc}: ${${NAME}_err}")
endmacro()

# rows(<csv> <out var>): the data lines (no '#' lines, no header) and the header as <out>_header.
function(rows file var)
  file(STRINGS ${file} lines)
  set(out "")
  set(header "")
  foreach(l IN LISTS lines)
    if(l MATCHES "^#")
      continue()
    elseif(header STREQUAL "")
      set(header "${l}")
    else()
      list(APPEND out "${l}")
    endif()
  endforeach()
  set(${var} "${out}" PARENT_SCOPE)
  set(${var}_header "${header}" PARENT_SCOPE)
endfunction()

# field(<header> <row> <column> <out var>): a column by name; empty fields kept.
function(field header row name var)
  string(REPLACE "," ";" cols "${header}")
  list(FIND cols "${name}" at)
  string(REGEX REPLACE "\"[^\"]*\"" "q" row "${row}")
  string(REPLACE "," ";" fields "${row}")
  set(v NOTFOUND)
  set(k 0)
  foreach(f IN LISTS fields)
    if(k EQUAL at)
      set(v "${f}")
      break()
    endif()
    math(EXPR k "${k} + 1")
  endforeach()
  set(${var} "${v}" PARENT_SCOPE)
endfunction()

# decimal(<number> <mantissa var> <exponent var>): a number as printed (%.6g, %.9g) as an
# integer mantissa of 10 digits (0 alone) times 10^exponent (CMake's math() has only integers).
function(decimal v mvar evar)
  if(NOT v MATCHES "^(-?)([0-9]*)(\\.([0-9]*))?([eE]([-+]?[0-9]+))?$")
    message(FATAL_ERROR "not a number: '${v}'")
  endif()
  set(sign "${CMAKE_MATCH_1}")
  set(digits "${CMAKE_MATCH_2}${CMAKE_MATCH_4}")
  string(LENGTH "${CMAKE_MATCH_4}" nfrac)
  set(e 0)
  if(NOT "${CMAKE_MATCH_6}" STREQUAL "")
    string(REGEX REPLACE "^\\+" "" e "${CMAKE_MATCH_6}")
  endif()
  math(EXPR e "${e} - ${nfrac}")
  string(REGEX REPLACE "^0+" "" digits "${digits}")
  string(LENGTH "${digits}" n)
  if(n GREATER 10) # keep 10 digits (1e-9 relative, far below the tolerances)
    math(EXPR cut "${n} - 10")
    string(SUBSTRING "${digits}" 0 10 digits)
    math(EXPR e "${e} + ${cut}")
  endif()
  if(digits STREQUAL "")
    set(digits 0)
  endif()
  while(n LESS 10 AND NOT digits STREQUAL "0") # 10 digits, so exponents compare
    string(APPEND digits 0)
    math(EXPR e "${e} - 1")
    math(EXPR n "${n} + 1")
  endwhile()
  set(${mvar} "${sign}${digits}" PARENT_SCOPE)
  set(${evar} "${e}" PARENT_SCOPE)
endfunction()

# near(<a> <b> <1/tol> <out var>): both empty, or |a - b| * (1/tol) <= |b|.
function(near a b inv_tol var)
  set(ok FALSE)
  if(a STREQUAL "" AND b STREQUAL "")
    set(ok TRUE)
  elseif(NOT a STREQUAL "" AND NOT b STREQUAL "")
    decimal("${a}" ma ea)
    decimal("${b}" mb eb)
    # to a common exponent; values more than 10x apart in exponent are not near
    math(EXPR de "${ea} - ${eb}")
    if(de GREATER -2 AND de LESS 2 OR ma EQUAL 0 OR mb EQUAL 0)
      if(de EQUAL 1)
        math(EXPR ma "${ma} * 10")
      elseif(de EQUAL -1)
        math(EXPR mb "${mb} * 10")
      endif()
      if(de GREATER -2 AND de LESS 2)
        math(EXPR d "${ma} - ${mb}")
        if(d LESS 0)
          math(EXPR d "-${d}")
        endif()
        if(mb LESS 0)
          math(EXPR mb "-${mb}")
        endif()
        math(EXPR lhs "${d} * ${inv_tol}")
        if(NOT lhs GREATER mb)
          set(ok TRUE)
        endif()
      endif()
    endif()
  endif()
  set(${var} ${ok} PARENT_SCOPE)
endfunction()

set(size --resolution 48x48)
# The bench: both settings over frames 0..3 (frame 0 warm-up, one scored frame, cheap refs).
file(WRITE ${OUT_DIR}/settings.txt "spp:spp=1,name=spp1\nsamplecache:name=sc\ndefault:name=default\n") # ';' would split the argument
run(bench bench --settings @${OUT_DIR}/settings.txt --frames 4 --warmup 1 --score-every 100
    ${size} --ref-spp 4 --anchor first --out ${OUT_DIR}/b --no-plots --quiet --validation)
# The same frames through the replay (direct path), and scored from the files.
run(rep_spp replay --direct --method spp --spp 1 ${size} --frames 4 --write exr
    --out ${OUT_DIR}/spp --quiet --validation)
# (a bench `samplecache` has neither the replay's blend, its TAA nor its variance-guided
# shading: all three named here)
run(rep_sc replay --direct --method samplecache --blend none --taa off --sc-shade uniform ${size} --frames 4 --write exr
    --out ${OUT_DIR}/sc --quiet --validation)
# Issue 19 item 1: the bench's setting `default` is what `xrsc replay` renders without a
# method, blend or TAA option (its figures equal the replay's, as for the other settings).
run(rep_def replay --direct ${size} --frames 4 --write exr --out ${OUT_DIR}/def --quiet
    --validation)
# OpenXR path: frames 1..3 of the same stream.
run(rep_xr replay --method spp --spp 1 ${size} --frames 3 --write exr --out ${OUT_DIR}/xr
    --quiet --validation)
foreach(d spp sc xr def)
  run(m_${d} metrics --stereo ${OUT_DIR}/${d} --warmup 1 --csv ${OUT_DIR}/${d}.csv --quiet)
endforeach()

rows(${OUT_DIR}/b/summary.csv summary)
# compare(<run> <bench setting> <tol> <exact counts>)
function(compare run setting tol exact)
  rows(${OUT_DIR}/b/frames/${setting}.csv bench)
  rows(${OUT_DIR}/${run}.csv mine)
  set(bad "")
  foreach(row IN LISTS mine)
    field("${mine_header}" "${row}" frame f)
    set(brow "")
    foreach(b IN LISTS bench)
      field("${bench_header}" "${b}" frame bf)
      if(bf STREQUAL f)
        set(brow "${b}")
      endif()
    endforeach()
    foreach(col temporal stereo)
      field("${mine_header}" "${row}" ${col}_msd mv)
      field("${bench_header}" "${brow}" ${col}_msd bv)
      field("${mine_header}" "${row}" ${col}_valid mn)
      field("${bench_header}" "${brow}" ${col}_valid bn)
      if(f STREQUAL "1" AND run STREQUAL "xr" AND col STREQUAL "temporal")
        continue() # the OpenXR run's first frame has no previous one; the bench's frame 1 has
      endif()
      near("${mv}" "${bv}" ${tol} ok)
      if(NOT ok OR (exact AND NOT "${mn}" STREQUAL "${bn}" AND NOT "${bn}" STREQUAL ""))
        string(APPEND bad " frame ${f} ${col}: ${mv} (${mn} px) vs bench ${bv} (${bn} px);")
      endif()
    endforeach()
  endforeach()
  list(LENGTH mine n)
  set(ok FALSE)
  if(bad STREQUAL "" AND n GREATER 2)
    set(ok TRUE)
  endif()
  check("${run}: per-frame temporal and stereo equal the bench's ${setting}" ok "${n} rows;${bad}")
  set(passed ${passed} PARENT_SCOPE)
  set(failed ${failed} PARENT_SCOPE)
endfunction()

compare(spp spp1 ${BENCH_REL_TOL} TRUE)
compare(sc sc ${BENCH_REL_TOL} TRUE)
compare(xr spp1 ${XR_REL_TOL} FALSE)
compare(def default ${BENCH_REL_TOL} TRUE)

# The means printed by `xrsc metrics --stereo` against the bench summary's.
foreach(pair "spp;spp1" "sc;sc" "def;default")
  list(GET pair 0 run)
  list(GET pair 1 setting)
  set(srow "")
  foreach(r IN LISTS summary)
    field("${summary_header}" "${r}" setting s)
    if(s STREQUAL setting)
      set(srow "${r}")
    endif()
  endforeach()
  field("${summary_header}" "${srow}" temporal_msd bt)
  field("${summary_header}" "${srow}" stereo_msd bs)
  string(REGEX MATCH "mean temporal ([^ ]+) \\(3 frames\\)" _ "${m_${run}_out}")
  set(mt "${CMAKE_MATCH_1}")
  string(REGEX MATCH "mean stereo +([^ ]+) \\(3 frames\\)" _ "${m_${run}_out}")
  set(ms "${CMAKE_MATCH_1}")
  near("${mt}" "${bt}" ${BENCH_REL_TOL} ok_t)
  near("${ms}" "${bs}" ${BENCH_REL_TOL} ok_s)
  set(ok FALSE)
  if(ok_t AND ok_s AND NOT bt STREQUAL "" AND NOT bs STREQUAL "")
    set(ok TRUE)
  endif()
  check("${run}: means equal the bench summary's" ok
        "temporal ${mt} vs ${bt}, stereo ${ms} vs ${bs}\n${m_${run}_out}")
endforeach()

# views.csv of both paths: the header, two rows per frame, the frames of the files.
foreach(pair "spp;0;3" "xr;1;3")
  list(GET pair 0 run)
  list(GET pair 1 first)
  list(GET pair 2 last)
  rows(${OUT_DIR}/${run}/views.csv v)
  list(LENGTH v n)
  math(EXPR want "2 * (${last} - ${first} + 1)")
  list(GET v 0 r0)
  list(GET v -1 rl)
  set(ok FALSE)
  if(v_header STREQUAL "frame,eye,display_time_ns,px,py,pz,qx,qy,qz,qw,angle_left,angle_right,angle_up,angle_down,width,height"
     AND n EQUAL want AND r0 MATCHES "^${first},left," AND rl MATCHES "^${last},right,.*,48,48$")
    set(ok TRUE)
  endif()
  check("${run}: views.csv has frames ${first}..${last}" ok "${v_header}\n${v}")
endforeach()

# A folder holding only a views.csv is an earlier run: refused without --overwrite.
file(MAKE_DIRECTORY ${OUT_DIR}/old)
file(COPY ${OUT_DIR}/spp/views.csv DESTINATION ${OUT_DIR}/old)
execute_process(COMMAND ${XRSC_EXE} replay --direct ${size} --frames 1 --out ${OUT_DIR}/old
                        --quiet RESULT_VARIABLE rc OUTPUT_QUIET ERROR_QUIET)
set(ok FALSE)
if(rc EQUAL 2)
  set(ok TRUE)
endif()
check("views.csv counts as an earlier run's file" ok "exit ${rc}")

message("${passed} passed, ${failed} failed")
if(failed GREATER 0)
  message(FATAL_ERROR "metrics_stereo_test failed")
endif()
