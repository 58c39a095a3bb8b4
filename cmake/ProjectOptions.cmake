# Warnings and sanitizers for project code only (third-party headers are SYSTEM includes).
add_library(dammloam_options INTERFACE)
target_compile_options(dammloam_options INTERFACE
  $<$<COMPILE_LANGUAGE:CXX>:-Wall -Wextra -Wpedantic -Wno-psabi>)

if(DAMMLOAM_SANITIZE AND DAMMLOAM_TSAN)
  message(FATAL_ERROR "DAMMLOAM_SANITIZE and DAMMLOAM_TSAN are mutually exclusive")
endif()
if(DAMMLOAM_SANITIZE)
  add_compile_options(-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
  add_link_options(-fsanitize=address,undefined)
endif()
if(DAMMLOAM_TSAN)
  # -Wno-tsan: GCC warns for every libstdc++ atomic_thread_fence (TBB, moodycamel) that TSan
  # does not model them; the races they would hide are listed in tests/support/tsan.supp.
  add_compile_options(-fsanitize=thread -fno-omit-frame-pointer)
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    add_compile_options(-Wno-tsan)
  endif()
  add_link_options(-fsanitize=thread)
endif()

# The compile flags every test executable shares (and tests/support's precompiled header with it).
function(dammloam_test_flags target)
  # Test code itself is compiled at -O1: the code under test lives in the libraries (-O3), and
  # gtest's macros at -O3 cost about 1.6x the compile time for nothing a test measures. Not
  # lower in the sanitizer builds: at -O0 their test files compiled in half the time, but the
  # suites' own helpers (ray casting, simulated runs, PCD comparisons) ran up to 10x slower
  # under ASan (the ASan+UBSan tests took 982 s instead of 273).
  target_compile_options(${target} PRIVATE $<$<CONFIG:Release>:-O1>)
  target_compile_definitions(${target} PRIVATE
    DAMMLOAM_SHARED_DATA_DIR="${CMAKE_SOURCE_DIR}/../shared/data"
    DAMMLOAM_SOURCE_DIR="${CMAKE_SOURCE_DIR}"
    DAMMLOAM_BIN_DIR="${CMAKE_BINARY_DIR}/bin")
endfunction()

# dammloam_add_test(NAME name SOURCES a.cpp... LIBS lib... [LABELS l...])
# One GoogleTest executable per suite; tests are discovered so ctest lists each case.
function(dammloam_add_test)
  cmake_parse_arguments(T "" "NAME" "SOURCES;LIBS;LABELS" ${ARGN})
  add_executable(${T_NAME} ${T_SOURCES})
  dammloam_test_flags(${T_NAME})
  target_link_libraries(${T_NAME} PRIVATE ${T_LIBS} GTest::gtest_main dammloam_options)
  if(TARGET dammloam_test_pch)
    target_precompile_headers(${T_NAME} REUSE_FROM dammloam_test_pch)
  endif()
  set_target_properties(${T_NAME} PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/tests)
  # gtest_discover_tests loses list escaping, so several labels become one joined label
  # ("sanitize-tsan"); `ctest -L` takes a regex, so -L sanitize and -L tsan both select it.
  string(REPLACE ";" "-" label "${T_LABELS}")
  gtest_discover_tests(${T_NAME} DISCOVERY_TIMEOUT 60 PROPERTIES LABELS "${label}")
  # One aggregate target per label (dammloam_tests_sanitize, dammloam_tests_tsan) so a
  # sanitizer build compiles only the suites it runs.
  foreach(l ${T_LABELS})
    if(NOT TARGET dammloam_tests_${l})
      add_custom_target(dammloam_tests_${l})
    endif()
    add_dependencies(dammloam_tests_${l} ${T_NAME})
  endforeach()
  # TBB's worker pool is not instrumented, so TSan reports its internal hand-offs as races.
  # Under TSan the tests run TBB loops inline (see tests/support) and TSan judges our threads.
  if(DAMMLOAM_TSAN)
    target_sources(${T_NAME} PRIVATE ${CMAKE_SOURCE_DIR}/tests/support/tbb_inline.cpp)
    target_link_libraries(${T_NAME} PRIVATE dammloam_core)
  endif()
endfunction()
