# Optional Embree 3 comparison backend for `fovref bench rays` (tools/cli/bench/embree.cpp). Never used
# by the reference path; the CLI builds without it. Debian: apt-get install libembree-dev.
find_package(embree 3 CONFIG QUIET)
if(embree_FOUND)
  message(STATUS "Embree ${embree_VERSION} found: fovref bench rays compares against it")
  target_compile_definitions(fovref_cli PRIVATE FOVREF_HAVE_EMBREE)
  target_link_libraries(fovref_cli PRIVATE embree)
else()
  message(STATUS "Embree not found: fovref bench rays runs without the comparison")
endif()
