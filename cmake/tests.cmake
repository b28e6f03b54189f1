# Test registration. Unit tests: one ctest entry per doctest test suite file group.
# CLI tests: shell scripts in tests/cli, run against the built fovref binary.
include(doctest)
doctest_discover_tests(fovref_tests WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})
# ... which reads the names as a CMake list: no name may hold a ';' (check_test_names.sh).
add_test(NAME core.test_names_register
  COMMAND bash ${PROJECT_SOURCE_DIR}/tools/scripts/check_test_names.sh $<TARGET_FILE:fovref_tests>)
add_test(NAME core.test_names_register_self_test
  COMMAND bash ${PROJECT_SOURCE_DIR}/tools/scripts/check_test_names.sh --self-test)

file(GLOB FOVREF_CLI_TESTS CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/tests/cli/*.sh)
foreach(script ${FOVREF_CLI_TESTS})
  get_filename_component(name ${script} NAME_WE)
  if(NOT FOVREF_GPU_CLIENTS AND name MATCHES "^(gl_client|vulkan_client)$")
    continue()  # the release build runs them (FOVREF_GPU_CLIENTS)
  endif()
  add_test(NAME cli.${name} COMMAND bash ${script} $<TARGET_FILE:fovref_cli> ${PROJECT_SOURCE_DIR})
  set_tests_properties(cli.${name} PROPERTIES WORKING_DIRECTORY ${PROJECT_BINARY_DIR})
endforeach()

# The renderer library must import no libm transcendental (SPEC §0).
add_test(NAME core.no_libm_transcendentals
  COMMAND bash ${PROJECT_SOURCE_DIR}/tools/scripts/check_no_libm.sh $<TARGET_FILE:fovref>)
add_test(NAME core.no_libm_in_cli
  COMMAND bash ${PROJECT_SOURCE_DIR}/tools/scripts/check_no_libm.sh $<TARGET_FILE:fovref_cli>)
add_test(NAME core.no_libm_check_self_test
  COMMAND ${CMAKE_COMMAND} -E env CXX=${CMAKE_CXX_COMPILER}
          bash ${PROJECT_SOURCE_DIR}/tools/scripts/check_no_libm.sh --self-test)

# Includes in ref/ point down the pipeline (docs/stage-framework.md, "Layers").
add_test(NAME core.include_layers COMMAND bash ${PROJECT_SOURCE_DIR}/tools/scripts/check_layers.sh)
add_test(NAME core.include_layers_self_test
  COMMAND bash ${PROJECT_SOURCE_DIR}/tools/scripts/check_layers.sh --self-test)

# AVX code clears the ymm upper halves before it calls SSE code (tools/scripts/check_vzeroupper.py;
# read from g++'s optimised code, where the instructions are the ones a bench times).
if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND CMAKE_BUILD_TYPE STREQUAL "Release")
  add_test(NAME core.vzeroupper_before_sse_calls
    COMMAND python3 ${PROJECT_SOURCE_DIR}/tools/scripts/check_vzeroupper.py $<TARGET_FILE:fovref_cli>)
endif()
add_test(NAME core.vzeroupper_check_self_test
  COMMAND python3 ${PROJECT_SOURCE_DIR}/tools/scripts/check_vzeroupper.py --self-test)
