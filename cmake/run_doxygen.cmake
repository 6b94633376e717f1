# Run by the `doc` target (cmake/doc.cmake): writes the main page, runs Doxygen, and fails when its
# warning log is not empty, printing the log.
#   cmake -DDOXYGEN=… -DDOXYFILE=… -DDOC_DIR=… -DLIBRARY_MD=… -DMAINPAGE=… -DDOCS_URL=… -P run_doxygen.cmake

# The main page: docs/library.md as GitHub shows it. Doxygen 1.9 makes no anchors of its own for
# Markdown headings, so each "## Heading" gets GitHub's anchor as an explicit {#id}; links to the other
# pages of docs/ (not part of the reference) go to the files in the source tree.
file(READ ${LIBRARY_MD} page)
string(REGEX MATCHALL "\n##+ [^\n]*" headings "${page}")
foreach(heading IN LISTS headings)
  string(REGEX REPLACE "^\n#+ " "" title "${heading}")
  string(TOLOWER "${title}" id)
  string(REGEX REPLACE "[^a-z0-9 _-]" "" id "${id}")
  string(REPLACE " " "-" id "${id}")
  string(REPLACE "${heading}\n" "${heading} {#${id}}\n" page "${page}")
endforeach()
string(REGEX REPLACE "\\]\\(([a-z0-9_]+\\.md)" "](${DOCS_URL}/\\1" page "${page}")
file(WRITE ${MAINPAGE} "${page}")

# A fresh tree each time: no page outlives its header.
file(REMOVE_RECURSE ${DOC_DIR}/html)
file(REMOVE ${DOC_DIR}/warnings.log)
execute_process(COMMAND ${DOXYGEN} ${DOXYFILE} WORKING_DIRECTORY ${DOC_DIR} RESULT_VARIABLE status)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "doc: doxygen failed (exit ${status})")
endif()
file(READ ${DOC_DIR}/warnings.log warnings)
if(NOT warnings STREQUAL "")
  string(REGEX MATCHALL "warning:" count "${warnings}")
  list(LENGTH count count)
  message("${warnings}")
  message(FATAL_ERROR "doc: ${count} Doxygen warning(s) above (${DOC_DIR}/warnings.log): fix the comments")
endif()
message(STATUS "doc: no warnings; ${DOC_DIR}/html/index.html")
