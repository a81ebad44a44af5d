# SPDX-License-Identifier: Apache-2.0
# The port's unitree_hg types and the fake robot's (two IDL files written
# apart) must carry the same XTypes type information, byte for byte: that
# is what Cyclone matches readers and writers on when both sides send it,
# as Unitree's SDKs do. Compares the TYPE_INFO/TYPE_MAP arrays idlc put in
# the two generated C files.
#   cmake -DPORT=<port's unitree_hg.c> -DFAKE=<fake's unitree_hg.c> -P check_g1_typeinfo.cmake
function(type_arrays file out)
  file(READ ${file} text)
  string(REGEX MATCHALL "#define TYPE_(INFO|MAP)_CDR_[A-Za-z0-9_]+ \\(unsigned char \\[\\]\\){[^}]*}"
         defs "${text}")
  set(result "")
  foreach(d IN LISTS defs)
    string(REGEX REPLACE "[ \t\r\n\\\\]" "" d "${d}")
    list(APPEND result "${d}")
  endforeach()
  set(${out} "${result}" PARENT_SCOPE)
endfunction()
type_arrays(${PORT} port)
type_arrays(${FAKE} fake)
list(LENGTH port n)
if(n LESS 10)
  message(FATAL_ERROR "found ${n} type arrays in ${PORT}; expected 10 (5 types)")
endif()
foreach(d IN LISTS port)
  string(REGEX MATCH "TYPE_(INFO|MAP)_CDR_[A-Za-z0-9_]+" name "${d}")
  list(FIND fake "${d}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "${name}: the port's type information differs from the fake robot's")
  endif()
  message(STATUS "${name}: same")
endforeach()
