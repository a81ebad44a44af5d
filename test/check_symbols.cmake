# SPDX-License-Identifier: Apache-2.0
# cmake -DLIB=libroz_core.a -DNM=nm -P check_symbols.cmake
# Fails if the library defines a global symbol outside roz_ (roz__ included)
# or references malloc/calloc/realloc/free, or the C library's printf family
# (roz formats its messages with roz_format(), roz/format.h: the same text
# on every C library, newlib-nano included, and no printf on firmware),
# where -DREFUSE_PRINTF=ON asks for it (the core, roz::can), and with it the
# locale functions (a message's text never depends on the locale).
execute_process(COMMAND ${NM} -g --defined-only ${LIB} OUTPUT_VARIABLE defined RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "nm failed on ${LIB}")
endif()
execute_process(COMMAND ${NM} -g --undefined-only ${LIB} OUTPUT_VARIABLE undefined)
string(REPLACE "\n" ";" lines "${defined}")
set(bad "")
set(count 0)
foreach(line IN LISTS lines)
  if(line MATCHES "^[0-9a-fA-F]+ [A-Za-z] (.+)$")
    math(EXPR count "${count} + 1")
    if(NOT CMAKE_MATCH_1 MATCHES "^roz_")
      list(APPEND bad ${CMAKE_MATCH_1})
    endif()
  endif()
endforeach()
if(bad)
  message(FATAL_ERROR "${LIB} exports symbols outside the roz_ prefix: ${bad}")
endif()
if(count EQUAL 0)
  message(FATAL_ERROR "${LIB}: no exported symbols found; is NM right?")
endif()
string(REPLACE "\n" ";" ulines "${undefined}")
foreach(line IN LISTS ulines)
  if(line MATCHES " U (malloc|calloc|realloc|free|aligned_alloc|posix_memalign)$")
    message(FATAL_ERROR "${LIB} calls ${CMAKE_MATCH_1}: the core must not allocate")
  endif()
  if(REFUSE_PRINTF AND
     line MATCHES " U (_*(v?s?n?printf|v?fprintf|v?dprintf|v?asprintf)(_chk)?)$")
    message(FATAL_ERROR "${LIB} calls ${CMAKE_MATCH_1}: roz's messages are formatted by "
                        "roz_format() (roz/format.h), never the C library's printf")
  endif()
  if(REFUSE_PRINTF AND line MATCHES " U (localeconv|setlocale|newlocale|uselocale)$")
    message(FATAL_ERROR "${LIB} calls ${CMAKE_MATCH_1}: roz's text is the same in every "
                        "locale (roz/format.h)")
  endif()
endforeach()
message(STATUS "${LIB}: ${count} exported symbols, all roz_; no heap calls, no printf")
