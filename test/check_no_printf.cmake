# SPDX-License-Identifier: Apache-2.0
# cmake -DROOT=<source tree> -P check_no_printf.cmake
# The sources a firmware links (the core, roz::hal, the loopback port and
# roz::can, the SocketCAN port's portable half) call no printf-family
# function: their messages go through roz_format()
# (roz/format.h), whose text is the same under every C library (newlib-nano
# prints no %lld, %zu or %g, and shifts the arguments after one). Also
# refused: conversions roz_format() does not have (%f, %e, %a, %n), which
# it would print as "%?". Not checked: the host-only libraries a firmware
# never builds (host/): roz::toml, which reads numbers with the C
# library's strtod, and roz::record, which writes files with stdio.
file(GLOB sources ${ROOT}/lib/src/*.c ${ROOT}/lib/src/*.h ${ROOT}/lib/include/roz/*.h
                  ${ROOT}/hal/src/*.c ${ROOT}/hal/include/roz/hal/*.h
                  ${ROOT}/ports/loopback/src/*.c ${ROOT}/ports/loopback/src/*.h
                  ${ROOT}/ports/loopback/include/roz/*.h ${ROOT}/ports/loopback/include/roz/port/*.h
                  ${ROOT}/ports/socketcan/src/mit_codec.c ${ROOT}/ports/socketcan/src/can_config.c
                  ${ROOT}/ports/socketcan/src/can_hold.c
                  ${ROOT}/ports/socketcan/include/roz/port/mit_codec.h
                  ${ROOT}/ports/socketcan/include/roz/port/can_config.h
                  ${ROOT}/ports/socketcan/include/roz/port/can_hold.h)
list(LENGTH sources n)
if(n LESS 20)
  message(FATAL_ERROR "only ${n} sources found under ${ROOT}: is ROOT right?")
endif()
set(bad "")
foreach(f IN LISTS sources)
  file(STRINGS ${f} lines)
  set(ln 0)
  foreach(line IN LISTS lines)
    math(EXPR ln "${ln} + 1")
    if(line MATCHES "(^|[^A-Za-z0-9_])(v?s?n?printf|v?fprintf|puts|fputs)\\(")
      list(APPEND bad "${f}:${ln}: ${CMAKE_MATCH_2}(): use roz_format()")
    endif()
    if(line MATCHES "\"[^\"]*%[-0-9.*]*(hh|h|ll|l|z|j|t|L)?[feaEFGAn][^\"]*\"")
      list(APPEND bad "${f}:${ln}: a conversion roz_format() does not have")
    endif()
  endforeach()
endforeach()
if(bad)
  string(REPLACE ";" "\n  " bad "${bad}")
  message(FATAL_ERROR "printf in firmware sources:\n  ${bad}")
endif()
message(STATUS "${n} firmware sources: no printf-family call, no unsupported conversion")
