# Helpers that give every sylva target the same flags and layout.

# -Wall includes -Wsign-compare in C++: the tree has no signed/unsigned
# comparison (checked when -Wno-sign-compare was dropped), keep it so.
set(SYLVA_WARNING_FLAGS -Wall -Wextra -Wpedantic)
set(SYLVA_SANITIZER_FLAGS -fsanitize=address,undefined -fno-omit-frame-pointer)
if(SYLVA_BUILD_FUZZERS)
  # Every target instrumented for coverage; the fuzz targets link libFuzzer.
  list(APPEND SYLVA_SANITIZER_FLAGS -fsanitize=fuzzer-no-link)
endif()

function(_sylva_common_target_settings target)
  target_compile_options(${target} PRIVATE ${SYLVA_WARNING_FLAGS})
  target_include_directories(${target} PUBLIC ${PROJECT_SOURCE_DIR})
  if(SYLVA_ENABLE_ASAN)
    target_compile_options(${target} PRIVATE ${SYLVA_SANITIZER_FLAGS})
    target_link_options(${target} PUBLIC ${SYLVA_SANITIZER_FLAGS})
  endif()
endfunction()

# sylva_add_library(NAME SRCS ... [PUBLIC_DEPS ...] [PRIVATE_DEPS ...])
# A static library whose includes are relative to the repository root.
function(sylva_add_library name)
  cmake_parse_arguments(ARG "" "" "SRCS;PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  add_library(${name} STATIC ${ARG_SRCS})
  _sylva_common_target_settings(${name})
  target_link_libraries(${name} PUBLIC ${ARG_PUBLIC_DEPS} PRIVATE ${ARG_PRIVATE_DEPS})
endfunction()

# sylva_add_executable(NAME SRCS ... [DEPS ...])
function(sylva_add_executable name)
  cmake_parse_arguments(ARG "" "" "SRCS;DEPS" ${ARGN})
  add_executable(${name} ${ARG_SRCS})
  _sylva_common_target_settings(${name})
  target_link_libraries(${name} PRIVATE ${ARG_DEPS})
endfunction()

# sylva_add_test(NAME SRCS ... [DEPS ...] [LABELS ...])
# A GoogleTest binary registered with CTest; tests run from the build tree.
function(sylva_add_test name)
  if(NOT SYLVA_BUILD_TESTS)
    return()
  endif()
  cmake_parse_arguments(ARG "" "TIMEOUT;SHARDS" "SRCS;DEPS;LABELS" ${ARGN})
  add_executable(${name} ${ARG_SRCS})
  _sylva_common_target_settings(${name})
  target_link_libraries(${name} PRIVATE ${ARG_DEPS} GTest::gtest GTest::gtest_main GTest::gmock)
  if(NOT ARG_TIMEOUT)
    set(ARG_TIMEOUT 600)
  endif()
  # Tests find checked-in data and built tools through these definitions.
  target_compile_definitions(${name} PRIVATE
    SYLVA_SOURCE_DIR="${PROJECT_SOURCE_DIR}" SYLVA_BINARY_DIR="${PROJECT_BINARY_DIR}")
  # SHARDS N: N CTest tests (name_shard_K), each running every N-th test
  # (GoogleTest's sharding), so that ctest -j spreads a long suite.
  set(tests ${name})
  set(environments "")
  if(ARG_SHARDS)
    set(tests "")
    math(EXPR last "${ARG_SHARDS} - 1")
    foreach(k RANGE ${last})
      add_test(NAME ${name}_shard_${k} COMMAND ${name})
      set_tests_properties(${name}_shard_${k} PROPERTIES ENVIRONMENT
        "GTEST_TOTAL_SHARDS=${ARG_SHARDS};GTEST_SHARD_INDEX=${k}")
      list(APPEND tests ${name}_shard_${k})
    endforeach()
  else()
    add_test(NAME ${name} COMMAND ${name})
  endif()
  foreach(test IN LISTS tests)
    set_tests_properties(${test} PROPERTIES TIMEOUT ${ARG_TIMEOUT})
    if(SYLVA_ENABLE_ASAN)
      set_property(TEST ${test} APPEND PROPERTY ENVIRONMENT
        "LSAN_OPTIONS=suppressions=${PROJECT_SOURCE_DIR}/cmake/lsan.supp:fast_unwind_on_malloc=0"
        "UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1")
    endif()
    if(ARG_LABELS)
      set_tests_properties(${test} PROPERTIES LABELS "${ARG_LABELS}")
    endif()
  endforeach()
endfunction()

# sylva_add_fuzzer(NAME DEPS...): a fuzz target (fuzz/NAME_fuzzer.cc): a
# libFuzzer binary NAME_fuzzer with SYLVA_BUILD_FUZZERS, else NAME_replay
# with replay_main.cc, registered with CTest on NAME's seeds (seeds.txt).
function(sylva_add_fuzzer name)
  if(SYLVA_BUILD_FUZZERS)
    add_executable(${name}_fuzzer ${name}_fuzzer.cc)
    target_link_options(${name}_fuzzer PRIVATE -fsanitize=fuzzer)
    set(target ${name}_fuzzer)
  else()
    add_executable(${name}_replay ${name}_fuzzer.cc replay_main.cc)
    set(target ${name}_replay)
  endif()
  _sylva_common_target_settings(${target})
  target_link_libraries(${target} PRIVATE ${ARGN})
  if(NOT SYLVA_BUILD_FUZZERS AND SYLVA_BUILD_TESTS)
    file(STRINGS ${PROJECT_SOURCE_DIR}/fuzz/seeds.txt lines REGEX "^${name} ")
    # A seed added to the list re-configures the build (the tests' arguments).
    set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS
                 ${PROJECT_SOURCE_DIR}/fuzz/seeds.txt)
    string(REGEX REPLACE "^${name} +" "" seeds "${lines}")
    separate_arguments(seeds UNIX_COMMAND "${seeds}")
    list(TRANSFORM seeds PREPEND ${PROJECT_SOURCE_DIR}/)
    add_test(NAME sylva_fuzz_replay_${name} COMMAND ${target} ${seeds})
    set_tests_properties(sylva_fuzz_replay_${name} PROPERTIES LABELS fuzz TIMEOUT 300)
  endif()
endfunction()

# sylva_forbid_links(TARGET LIBRARY...): a configure error if TARGET links any
# of the LIBRARIES, directly or through the sylva_* libraries it links. It
# keeps light targets light: the fuzz build compiles what its targets link.
function(sylva_forbid_links target)
  set(seen "")
  set(queue ${target})
  while(queue)
    list(POP_FRONT queue current)
    if(current IN_LIST seen OR NOT TARGET ${current})
      continue()
    endif()
    list(APPEND seen ${current})
    get_target_property(direct ${current} LINK_LIBRARIES)
    get_target_property(interface ${current} INTERFACE_LINK_LIBRARIES)
    foreach(library IN LISTS direct interface)
      # A static library's private dependencies appear as $<LINK_ONLY:...>.
      string(REGEX REPLACE "^\\$<LINK_ONLY:(.*)>$" "\\1" library "${library}")
      if(library IN_LIST ARGN)
        message(FATAL_ERROR "${target} links ${library} (through ${current}); it must not: "
                            "its build would compile all of ${library}")
      endif()
      if(library MATCHES "^sylva_")
        list(APPEND queue ${library})
      endif()
    endforeach()
  endwhile()
endfunction()
