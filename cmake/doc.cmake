# The `doc` target: the API reference, Doxygen over the installed headers (docs/Doxyfile.in) into
# build/doc/html/. It fails, printing the log, when Doxygen warns about anything: a wrong \param
# name, an unknown command, markup it cannot read. Included from the top-level CMakeLists.txt.
find_package(Doxygen QUIET)
if(NOT DOXYGEN_FOUND)
  message(STATUS "pcl_patchdict: doxygen not found: the `doc` target (API reference) is unavailable")
  return()
endif()

set(PCL_PATCHDICT_DOC_DIR ${CMAKE_CURRENT_BINARY_DIR}/doc)
# The main page is docs/library.md, rewritten at build time by cmake/run_doxygen.cmake into
# ${PCL_PATCHDICT_DOC_DIR}/mainpage.md (GitHub's heading anchors made explicit for Doxygen 1.9,
# links to the other docs/ pages pointed at the source tree).
set(PCL_PATCHDICT_DOC_MAINPAGE ${PCL_PATCHDICT_DOC_DIR}/mainpage.md)
configure_file(${CMAKE_CURRENT_SOURCE_DIR}/docs/Doxyfile.in ${PCL_PATCHDICT_DOC_DIR}/Doxyfile @ONLY)

file(GLOB_RECURSE PCL_PATCHDICT_DOC_HEADERS CONFIGURE_DEPENDS
     ${CMAKE_CURRENT_SOURCE_DIR}/include/pcl_patchdict/*.h ${CMAKE_CURRENT_SOURCE_DIR}/include/pcl_patchdict/*.hpp)
add_custom_target(doc
  COMMAND ${CMAKE_COMMAND} -DDOXYGEN=${DOXYGEN_EXECUTABLE} -DDOXYFILE=${PCL_PATCHDICT_DOC_DIR}/Doxyfile
          -DDOC_DIR=${PCL_PATCHDICT_DOC_DIR} -DLIBRARY_MD=${CMAKE_CURRENT_SOURCE_DIR}/docs/library.md
          -DMAINPAGE=${PCL_PATCHDICT_DOC_MAINPAGE} -DDOCS_URL=file://${CMAKE_CURRENT_SOURCE_DIR}/docs
          -P ${CMAKE_CURRENT_SOURCE_DIR}/cmake/run_doxygen.cmake
  SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/docs/Doxyfile.in ${CMAKE_CURRENT_SOURCE_DIR}/docs/library.md
  COMMENT "API reference (Doxygen ${DOXYGEN_VERSION}): ${PCL_PATCHDICT_DOC_DIR}/html/index.html"
  VERBATIM)
