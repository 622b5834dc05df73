# Checks of the module graph that the include paths alone do not enforce (docs/architecture.md,
# "Layout"). The run engine reaches the simulator only through its StepPredictor interface
# (tocd/acquisition/step_predictor.hpp): tocd_acquisition links no tocd_sim_* library, not even
# through the libraries it links, and no file under acquisition/ includes a tocd/sim/ header.
#
# tocd_check_layering() runs both checks when the build is configured (after every module is
# defined; a violation stops cmake); the include check also runs as the ctest test
# `layering.acquisition` (label unit), so that an include added without configuring again
# fails too. In script mode (cmake -DTOCD_LAYERING_SOURCE_DIR=DIR -P TocdLayering.cmake) this
# file runs the include check alone.

# Every target `target` links, directly or through the link interfaces of what it links
# (private dependencies of static libraries included: they are linked into every user).
function(tocd_link_closure target out)
  set(seen "")
  set(queue ${target})
  while(queue)
    list(POP_FRONT queue t)
    if(TARGET ${t})
      get_target_property(aliased ${t} ALIASED_TARGET)
      if(aliased)
        set(t ${aliased})
      endif()
    endif()
    if(t IN_LIST seen)
      continue()
    endif()
    list(APPEND seen ${t})
    if(NOT TARGET ${t})
      continue()
    endif()
    set(libs "")
    get_target_property(direct ${t} LINK_LIBRARIES)
    if(direct)
      list(APPEND libs ${direct})
    endif()
    get_target_property(iface ${t} INTERFACE_LINK_LIBRARIES)
    if(iface)
      list(APPEND libs ${iface})
    endif()
    foreach(lib IN LISTS libs)
      string(REGEX REPLACE "^\\$<LINK_ONLY:(.*)>$" "\\1" lib "${lib}")
      if(NOT lib MATCHES "^\\$<")
        list(APPEND queue ${lib})
      endif()
    endforeach()
  endwhile()
  list(REMOVE_ITEM seen ${target})
  set(${out} ${seen} PARENT_SCOPE)
endfunction()

# The lines of files under `dir` that include a header matching `header_regex`
# ("FILE: LINE" each).
function(tocd_find_includes dir header_regex out)
  file(GLOB_RECURSE files ${dir}/*.hpp ${dir}/*.cpp ${dir}/*.h ${dir}/*.in)
  set(found "")
  foreach(f IN LISTS files)
    file(STRINGS ${f} lines REGEX "^[ \t]*#[ \t]*include[ \t]*[<\"]${header_regex}")
    foreach(line IN LISTS lines)
      file(RELATIVE_PATH rel ${dir}/.. ${f})
      list(APPEND found "${rel}: ${line}")
    endforeach()
  endforeach()
  set(${out} ${found} PARENT_SCOPE)
endfunction()

function(tocd_check_acquisition_includes source_dir)
  tocd_find_includes(${source_dir}/acquisition "tocd/sim/" found)
  if(found)
    list(JOIN found "\n  " lines)
    message(FATAL_ERROR
      "acquisition/ includes the simulator; it may reach it only through StepPredictor "
      "(tocd/acquisition/step_predictor.hpp; the simulator's side is in analysis/):\n  ${lines}")
  endif()
endfunction()

function(tocd_check_layering)
  tocd_link_closure(tocd_acquisition linked)
  set(sim_libs ${linked})
  list(FILTER sim_libs INCLUDE REGEX "^tocd_sim")
  if(sim_libs)
    list(JOIN sim_libs ", " names)
    message(FATAL_ERROR
      "tocd_acquisition links the simulator (${names}), directly or through a library it links; "
      "the run engine may reach it only through StepPredictor (tocd/acquisition/step_predictor.hpp), "
      "implemented in analysis/ (docs/architecture.md)")
  endif()
  tocd_check_acquisition_includes(${PROJECT_SOURCE_DIR})
endfunction()

if(CMAKE_SCRIPT_MODE_FILE STREQUAL CMAKE_CURRENT_LIST_FILE)
  if(NOT TOCD_LAYERING_SOURCE_DIR)
    message(FATAL_ERROR "usage: cmake -DTOCD_LAYERING_SOURCE_DIR=<source dir> -P TocdLayering.cmake")
  endif()
  tocd_check_acquisition_includes(${TOCD_LAYERING_SOURCE_DIR})
  message(STATUS "acquisition/ includes no tocd/sim/ header")
endif()
