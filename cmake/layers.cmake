# The project's layers: one folder each, built as one target, linking only the layers below it.
#
#   gibench_layer(<target> <folder> [<layer below>...] [EXCLUDE <file>...] [EXECUTABLE])
#     builds <folder>/*.cpp (not its subfolders) as a static library (an executable with
#     EXECUTABLE) that links the named layers. A folder's headers may include its own folder's
#     and those of every layer it depends on, directly or through others.
#   gibench_layer_check()
#     after the last layer: adds a build step that fails, naming the file and line, when an
#     include breaks that rule or a source file lies in a folder that is no layer.

function(gibench_layer target folder)
  cmake_parse_arguments(PARSE_ARGV 2 arg "EXECUTABLE" "" "EXCLUDE")
  set(dependencies ${arg_UNPARSED_ARGUMENTS})
  file(GLOB sources CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/${folder}/*.cpp)
  foreach(excluded IN LISTS arg_EXCLUDE)
    list(REMOVE_ITEM sources ${PROJECT_SOURCE_DIR}/${folder}/${excluded})
  endforeach()
  if(NOT sources)
    message(FATAL_ERROR "layer ${target}: no .cpp file in ${folder}")
  endif()
  if(arg_EXECUTABLE)
    add_executable(${target} ${sources})
    target_link_libraries(${target} PRIVATE ${dependencies})
  else()
    add_library(${target} STATIC ${sources})
    target_link_libraries(${target} PUBLIC ${dependencies})
  endif()
  target_include_directories(${target} PUBLIC ${PROJECT_SOURCE_DIR})
  target_compile_options(${target} PRIVATE ${GIBENCH_WARNINGS})
  target_compile_definitions(${target} PRIVATE GIBENCH_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
  set_property(GLOBAL APPEND PROPERTY GIBENCH_LAYERS ${target})
  set_property(GLOBAL PROPERTY GIBENCH_LAYER_FOLDER_${target} ${folder})
  set_property(GLOBAL PROPERTY GIBENCH_LAYER_DEPENDENCIES_${target} ${dependencies})
endfunction()

# The folders `target` may include from: its own and those of every layer below it.
function(gibench_layer_reach target out)
  set(pending ${target})
  set(seen "")
  set(folders "")
  while(pending)
    list(POP_FRONT pending layer)
    if(layer IN_LIST seen)
      continue()
    endif()
    list(APPEND seen ${layer})
    get_property(folder GLOBAL PROPERTY GIBENCH_LAYER_FOLDER_${layer})
    get_property(below GLOBAL PROPERTY GIBENCH_LAYER_DEPENDENCIES_${layer})
    list(APPEND folders ${folder})
    foreach(dependency IN LISTS below)
      get_property(known GLOBAL PROPERTY GIBENCH_LAYER_FOLDER_${dependency} SET)
      if(known)
        list(APPEND pending ${dependency})
      endif()
    endforeach()
  endwhile()
  set(${out} ${folders} PARENT_SCOPE)
endfunction()

function(gibench_layer_check)
  get_property(layers GLOBAL PROPERTY GIBENCH_LAYERS)
  set(rules "")
  foreach(layer IN LISTS layers)
    get_property(folder GLOBAL PROPERTY GIBENCH_LAYER_FOLDER_${layer})
    gibench_layer_reach(${layer} reach)
    list(JOIN reach "," reach_text)
    string(APPEND rules "${folder}=${reach_text}\n")
  endforeach()
  # Every source below the layered roots, so that a file in a folder that is no layer is caught.
  file(GLOB_RECURSE all_sources CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/core/*.h ${PROJECT_SOURCE_DIR}/core/*.cpp
       ${PROJECT_SOURCE_DIR}/methods/*.h ${PROJECT_SOURCE_DIR}/methods/*.cpp
       ${PROJECT_SOURCE_DIR}/experiments/*.h ${PROJECT_SOURCE_DIR}/experiments/*.cpp)
  set(rules_file ${PROJECT_BINARY_DIR}/layers.txt)
  file(CONFIGURE OUTPUT ${rules_file} CONTENT "${rules}")
  set(stamp ${PROJECT_BINARY_DIR}/layers.checked)
  add_custom_command(
    OUTPUT ${stamp}
    COMMAND ${CMAKE_COMMAND} -DRULES=${rules_file} -DSOURCE_DIR=${PROJECT_SOURCE_DIR} -DSTAMP=${stamp}
            -P ${PROJECT_SOURCE_DIR}/cmake/check_layers.cmake
    DEPENDS ${all_sources} ${rules_file} ${PROJECT_SOURCE_DIR}/cmake/check_layers.cmake
    COMMENT "Checking that every include follows the layers (docs/architecture.md)"
    VERBATIM)
  add_custom_target(gibench_layer_check ALL DEPENDS ${stamp})
  foreach(layer IN LISTS layers)
    add_dependencies(${layer} gibench_layer_check)
  endforeach()
endfunction()
