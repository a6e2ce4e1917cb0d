# SPDX-License-Identifier: MIT
# cmake -DIN=x.spv -DOUT=x.c -DIDENT=name -P embed_spirv.cmake: writes a uint32_t array.
file(READ ${IN} hex HEX)
string(LENGTH "${hex}" n)
math(EXPR bytes "${n} / 2")
math(EXPR rem "${bytes} % 4")
if(NOT rem EQUAL 0)
  message(FATAL_ERROR "${IN}: SPIR-V size ${bytes} is not a multiple of 4")
endif()
# little-endian bytes b0 b1 b2 b3 -> 0xb3b2b1b0
string(REGEX REPLACE "([0-9a-f][0-9a-f])([0-9a-f][0-9a-f])([0-9a-f][0-9a-f])([0-9a-f][0-9a-f])" "0x\\4\\3\\2\\1u," words "${hex}")
file(WRITE ${OUT} "/* generated from ${IN} */\n#include <stddef.h>\n#include <stdint.h>\nconst uint32_t ${IDENT}[] = {${words}};\nconst size_t ${IDENT}_size = ${bytes};\n")
