# SPDX-License-Identifier: Apache-2.0
# roz from C++ (docs/install.md, "Compile-time sizes"): every public header compiles alone in
# C++11, 14, 17 and 20 (-Wall -Wextra -Werror -pedantic), and consumer.cpp,
# which includes them all, builds against the libraries and runs.
# cmake -DCXX=... -DINCLUDES="a;b" -DHEADERS="roz/x.h;..." -DLIBS="lib.a;..."
#       -DSOURCE=consumer.cpp -DWORK=dir -P check_cxx.cmake
if(NOT CXX)
  message(FATAL_ERROR "no C++ compiler found (g++ or clang++): tools/setup.sh installs g++")
endif()
set(incs "")
foreach(d IN LISTS INCLUDES)
  list(APPEND incs -I${d})
endforeach()
file(MAKE_DIRECTORY ${WORK})
set(n 0)
foreach(h IN LISTS HEADERS)
  string(MAKE_C_IDENTIFIER "${h}" id)
  file(WRITE ${WORK}/${id}.cpp "#include \"${h}\"\n")
  foreach(std IN ITEMS c++11 c++14 c++17 c++20)
    execute_process(COMMAND ${CXX} -std=${std} -fsyntax-only -Wall -Wextra -Werror -pedantic
                            ${incs} ${WORK}/${id}.cpp
                    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
    if(NOT rc EQUAL 0)
      message(FATAL_ERROR "${h} does not compile as ${std}:\n${out}")
    endif()
    math(EXPR n "${n} + 1")
  endforeach()
endforeach()
message(STATUS "${n} header x standard compilations as C++")
execute_process(COMMAND ${CXX} -std=c++11 -Wall -Wextra -Werror -pedantic ${incs} ${SOURCE}
                        -o ${WORK}/consumer ${LIBS} -lm -lpthread
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "consumer.cpp does not build:\n${out}")
endif()
execute_process(COMMAND ${WORK}/consumer RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "consumer.cpp failed (${rc}):\n${out}")
endif()
message(STATUS "${out}")
