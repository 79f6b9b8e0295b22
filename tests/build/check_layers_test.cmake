# cmake/check_layers.cmake on a small tree: an upward include and a folder that is no layer must
# fail with the file, line and rule named; the same tree without them must pass.
#   cmake -DCHECKER=cmake/check_layers.cmake -DWORK=<scratch folder> -P tests/build/check_layers_test.cmake

cmake_policy(VERSION 3.25)

function(write_tree root bad)
  file(REMOVE_RECURSE ${root})
  file(WRITE ${root}/core/util/vec.h "#pragma once\n")
  file(WRITE ${root}/core/render/tracer.h "#pragma once\n#include \"core/util/vec.h\"\n#include <vector>\n")
  file(WRITE ${root}/core/util/vec.cpp "#include \"core/util/vec.h\"\n")
  if(bad)
    file(APPEND ${root}/core/util/vec.cpp "\n#include \"core/render/tracer.h\"\n")
    file(WRITE ${root}/methods/stray/stray.cpp "#include \"core/util/vec.h\"\n")
  endif()
  file(WRITE ${root}/layers.txt "core/util=core/util\ncore/render=core/render,core/util\n")
endfunction()

function(run_checker root result output)
  execute_process(COMMAND ${CMAKE_COMMAND} -DRULES=${root}/layers.txt -DSOURCE_DIR=${root} -P ${CHECKER}
                  RESULT_VARIABLE code ERROR_VARIABLE err OUTPUT_VARIABLE out)
  set(${result} ${code} PARENT_SCOPE)
  set(${output} "${out}${err}" PARENT_SCOPE)
endfunction()

write_tree(${WORK}/good FALSE)
run_checker(${WORK}/good code text)
if(NOT code EQUAL 0)
  message(FATAL_ERROR "a tree that follows its layers was rejected:\n${text}")
endif()

write_tree(${WORK}/bad TRUE)
run_checker(${WORK}/bad code text)
if(code EQUAL 0)
  message(FATAL_ERROR "an upward include and a stray folder passed the layer check")
endif()
string(REGEX REPLACE "[ \t\r\n]+" " " flat "${text}")
foreach(expected
    "core/util/vec.cpp:3: includes core/render/tracer.h, but layer core/util may include only from core/util"
    "methods/stray/stray.cpp: its folder methods/stray is no layer")
  string(FIND "${flat}" "${expected}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "the layer check's message lacks \"${expected}\":\n${text}")
  endif()
endforeach()
file(REMOVE_RECURSE ${WORK})
