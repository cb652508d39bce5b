# maxslice_module(NAME SOURCES ... [DEPS ...] [PRIVATE_DEPS ...])
# Declares one static library per module: public headers live in include/maxslice/<NAME>/,
# sources in src/<NAME>/. Only the modules listed in DEPS are visible to it, so an include
# that points back up the pipeline fails to build.
function(maxslice_module name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS;PRIVATE_DEPS" ${ARGN})
  add_library(maxslice_${name} STATIC ${ARG_SOURCES})
  add_library(maxslice::${name} ALIAS maxslice_${name})
  target_include_directories(maxslice_${name}
    PUBLIC $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/include>
    PRIVATE ${CMAKE_CURRENT_SOURCE_DIR})
  target_link_libraries(maxslice_${name} PUBLIC ${ARG_DEPS} PRIVATE ${ARG_PRIVATE_DEPS})
  set_target_properties(maxslice_${name} PROPERTIES POSITION_INDEPENDENT_CODE ON)
endfunction()
