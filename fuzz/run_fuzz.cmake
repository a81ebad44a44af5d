# SPDX-License-Identifier: Apache-2.0
# Runs one libFuzzer target as a test (cmake -P):
#   -DFUZZER=exe -DWORK=dir -DSECONDS=n [-DSEEDS=dir;dir...]
#       fuzz for SECONDS seconds (the environment's ROZ_FUZZ_SECONDS, when
#       set, wins: the longer runs of fuzz/README.md), from seed 1 (random
#       in the longer runs; ROZ_FUZZ_SEED wins); WORK/corpus is the growing corpus, every
#       *.wasm of the SEEDS folders is a read-only seed; a crash is written
#       to WORK/artifacts/ and fails the test
#   -DFUZZER=exe -DREPRODUCERS=dir
#       run every file in dir once (none may crash); passes when dir is empty
if(REPRODUCERS)
  file(GLOB inputs ${REPRODUCERS}/*)
  list(FILTER inputs EXCLUDE REGEX "README")
  if(NOT inputs)
    message(STATUS "no reproducers in ${REPRODUCERS}")
    return()
  endif()
  execute_process(COMMAND ${FUZZER} -runs=1 ${inputs} RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "a reproducer crashed ${FUZZER} (exit ${rc})")
  endif()
  list(LENGTH inputs n)
  message(STATUS "${n} reproducers ran clean")
  return()
endif()

# The short run of `make test` starts from a fixed seed, so a clean tree
# fuzzes the same way every time; the longer runs (ROZ_FUZZ_SECONDS set)
# take a random one (libFuzzer's -seed=0). ROZ_FUZZ_SEED wins over both.
set(SEED 1)
if(DEFINED ENV{ROZ_FUZZ_SECONDS})
  set(SECONDS $ENV{ROZ_FUZZ_SECONDS})
  set(SEED 0)
endif()
if(DEFINED ENV{ROZ_FUZZ_SEED})
  set(SEED $ENV{ROZ_FUZZ_SEED})
endif()
set(corpus ${WORK}/corpus)
set(seeds ${WORK}/seeds)
set(artifacts ${WORK}/artifacts)
file(REMOVE_RECURSE ${seeds})
file(MAKE_DIRECTORY ${corpus} ${seeds} ${artifacts})
foreach(dir IN LISTS SEEDS)
  file(GLOB wasm ${dir}/*.wasm)
  if(wasm)
    file(COPY ${wasm} DESTINATION ${seeds})
  endif()
endforeach()
execute_process(COMMAND ${FUZZER} -seed=${SEED} -max_total_time=${SECONDS} -timeout=10 -rss_limit_mb=2048
                        -print_final_stats=1 -artifact_prefix=${artifacts}/ ${corpus} ${seeds}
                RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${FUZZER} found a crash (exit ${rc}); the input is in ${artifacts}/")
endif()
