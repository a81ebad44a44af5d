# SPDX-License-Identifier: Apache-2.0
# cmake -DIN=controller.wasm -DOUT=controller_wasm.c -P embed_wasm.cmake
# Writes the module's bytes as the C array the image links (fw_wasm,
# fw_wasm_len): generated at build time from the .wasm the build made, never
# committed.
file(READ ${IN} hex HEX)
string(LENGTH "${hex}" n)
math(EXPR bytes "${n} / 2")
string(REGEX REPLACE "([0-9a-f][0-9a-f])" "0x\\1," body "${hex}")
# twelve bytes a line
string(REGEX REPLACE "((0x[0-9a-f][0-9a-f],){12})" "\\1\n    " body "${body}")
get_filename_component(name ${IN} NAME)
file(WRITE ${OUT}.tmp
"/* Generated from ${name} by embed_wasm.cmake at build time. DO NOT EDIT. */\n"
"#include <stddef.h>\n#include <stdint.h>\n\n"
"extern const uint8_t fw_wasm[];\nextern const size_t fw_wasm_len;\n\n"
"const uint8_t fw_wasm[] = {\n    ${body}\n};\n"
"const size_t fw_wasm_len = ${bytes};\n")
file(COPY_FILE ${OUT}.tmp ${OUT} ONLY_IF_DIFFERENT)
file(REMOVE ${OUT}.tmp)
