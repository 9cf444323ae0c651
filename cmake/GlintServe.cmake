# glint serve (src/glint/serve/, docs/preview.md): the live preview in the
# browser, a library of its own linked by the CLI, built when Debian's
# libcpp-httplib-dev is found (like Embree and MPI, optional).
option(GLINT_SERVE "Build glint serve, the live preview in the browser, when cpp-httplib is found" ON)
set(GLINT_WITH_SERVE OFF)
if(GLINT_SERVE)
  find_package(PkgConfig QUIET)
  if(PkgConfig_FOUND)
    pkg_check_modules(HTTPLIB QUIET IMPORTED_TARGET cpp-httplib)
  endif()
  if(HTTPLIB_FOUND)
    message(STATUS "cpp-httplib ${HTTPLIB_VERSION}: glint serve is built")
    set(GLINT_WITH_SERVE ON)
    file(GLOB GLINT_WEB_FILES CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/web/*.html ${PROJECT_SOURCE_DIR}/web/*.js
         ${PROJECT_SOURCE_DIR}/web/*.css ${PROJECT_SOURCE_DIR}/web/*.svg)
    set(GLINT_ASSETS_CPP ${PROJECT_BINARY_DIR}/generated/serve_assets.cpp)
    # "|" between the files: a ";" would split the command.
    string(REPLACE ";" "|" GLINT_WEB_FILE_LIST "${GLINT_WEB_FILES}")
    add_custom_command(OUTPUT ${GLINT_ASSETS_CPP}
      COMMAND ${CMAKE_COMMAND} -DOUTPUT=${GLINT_ASSETS_CPP} -DFILES=${GLINT_WEB_FILE_LIST}
              -P ${PROJECT_SOURCE_DIR}/cmake/embed_assets.cmake
      VERBATIM
      DEPENDS ${GLINT_WEB_FILES} ${PROJECT_SOURCE_DIR}/cmake/embed_assets.cmake
      COMMENT "Embedding web/ into glint serve")
    file(GLOB GLINT_SERVE_SOURCES CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/src/glint/serve/*.cpp
         ${PROJECT_SOURCE_DIR}/src/glint/serve/*.h)
    add_library(glint_serve STATIC ${GLINT_SERVE_SOURCES} ${GLINT_ASSETS_CPP})
    target_link_libraries(glint_serve PUBLIC glint PRIVATE PkgConfig::HTTPLIB nlohmann_json::nlohmann_json glint_warnings)
    if(NOT GLINT_PLUGINS)  # else the plugin glint-serve.so (cmake/GlintProgram.cmake)
      target_link_libraries(glint_cli PRIVATE glint_serve)
    endif()
    # On the two files that ask, not the whole program: building glint serve
    # later (scripts/test.sh after scripts/setup.sh) recompiles only those.
    set_property(SOURCE cli/main.cpp cli/serve.cpp APPEND PROPERTY COMPILE_DEFINITIONS GLINT_HAVE_SERVE=1)
  else()
    message(STATUS "cpp-httplib not found: glint is built without glint serve")
  endif()
endif()
