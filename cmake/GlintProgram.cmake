# The command-line program's own start-up (src/glint/program/): its heap,
# and its heavy optional parts as plugins loaded when used.

# The heap: big blocks from malloc's heap, grown ahead in huge pages
# (src/glint/program/memory.cpp).
target_sources(glint_cli PRIVATE src/glint/program/memory.cpp)

# The plugins (src/glint/program/plugin.h): glint-embree.so, glint-assimp.so,
# glint-mpi.so and glint-serve.so beside the program in the build tree, in
# ${CMAKE_INSTALL_LIBDIR}/glint once installed. The program links a proxy for
# each (the same functions, forwarding to the plugin) and, with --as-needed,
# none of the libraries behind them: a run that uses none of them maps and
# relocates none of them (about 20 ms a start; docs/performance.md). The
# library and everything else linking it are unchanged.
if(NOT GLINT_PLUGINS)
  return()
endif()
file(RELATIVE_PATH GLINT_PLUGIN_SUBDIR ${CMAKE_INSTALL_FULL_BINDIR} ${CMAKE_INSTALL_FULL_LIBDIR}/glint)
target_sources(glint_cli PRIVATE src/glint/program/plugin.cpp src/glint/program/plugin.h src/glint/program/api.h)
target_compile_definitions(glint_cli PRIVATE GLINT_PLUGIN_SUBDIR="${GLINT_PLUGIN_SUBDIR}")
target_link_libraries(glint_cli PRIVATE ${CMAKE_DL_LIBS})
target_link_options(glint_cli PRIVATE LINKER:--as-needed)

# glint_plugin(NAME LIBRARY...): glint-NAME.so from program/NAME_plugin.cpp
# and the libraries, and program/NAME_proxy.cpp in the program.
function(glint_plugin name)
  set(target glint_plugin_${name})
  add_library(${target} MODULE src/glint/program/${name}_plugin.cpp)
  set_target_properties(${target} PROPERTIES OUTPUT_NAME glint-${name} PREFIX "" SUFFIX ".so"
    LIBRARY_OUTPUT_DIRECTORY ${PROJECT_BINARY_DIR})
  target_link_libraries(${target} PRIVATE ${ARGN} glint_warnings)
  # The archives' symbols stay inside the plugin: it exports its entry point only.
  target_link_options(${target} PRIVATE LINKER:--exclude-libs,ALL)
  if(NOT GLINT_SANITIZE)
    target_link_options(${target} PRIVATE LINKER:--no-undefined)
  endif()
  target_sources(glint_cli PRIVATE src/glint/program/${name}_proxy.cpp)
  add_dependencies(glint_cli ${target})  # the program is not whole without its plugins
  install(TARGETS ${target} LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}/glint)
endfunction()

if(GLINT_WITH_EMBREE)
  glint_plugin(embree glint)  # the archive brings Embree (a private dependency of glint)
endif()
if(GLINT_WITH_ASSIMP)
  glint_plugin(assimp glint)
endif()
if(GLINT_WITH_MPI)
  glint_plugin(mpi glint_mpi)
endif()
if(GLINT_WITH_SERVE)
  glint_plugin(serve glint_serve)
endif()
