# Precompiled headers (FOVREF_PCH): the headers most translation units parse, compiled once per
# target. Each CLI command parses CLI11 (about 7 s a translation unit, header-only in Debian 12)
# and nlohmann/json (2.5 s); each test file doctest. Build time only: a precompiled header holds
# declarations and the same definitions a #include gives, so the code generated is the same.
if(NOT FOVREF_PCH)
  return()
endif()
set(FOVREF_PCH_STD <algorithm> <array> <cmath> <cstdint> <cstdio> <functional> <limits> <map>
    <memory> <optional> <string> <utility> <vector>)
target_precompile_headers(fovref PRIVATE ${FOVREF_PCH_STD} <glm/glm.hpp>)
target_precompile_headers(fovref_cli PRIVATE ${FOVREF_PCH_STD} <filesystem> <glm/glm.hpp>
    <CLI/CLI.hpp> <nlohmann/json.hpp>)
target_precompile_headers(fovref_tests PRIVATE ${FOVREF_PCH_STD} <glm/glm.hpp> <doctest/doctest.h>)
# doctest's implementation and main: DOCTEST_CONFIG_IMPLEMENT_WITH_MAIN must come before its
# first #include of doctest.h
set_source_files_properties(${PROJECT_SOURCE_DIR}/tests/core/test_main.cpp
    PROPERTIES SKIP_PRECOMPILE_HEADERS ON)
