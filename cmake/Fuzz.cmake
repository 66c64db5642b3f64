# libFuzzer targets (fuzz/, docs in fuzz/README.md): cmake -DSYLVA_FUZZ=ON with clang, usually
# together with -DSYLVA_SANITIZE=address,undefined (.ci/sanitize.sh). Every sylva library is then
# built with coverage instrumentation (-fsanitize=fuzzer-no-link), so the unit tests and the fuzz
# targets share one compilation; only the fuzz executables link libFuzzer's main.
option(SYLVA_FUZZ "build the libFuzzer targets in fuzz/ (clang only)" OFF)
if(SYLVA_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "SYLVA_FUZZ needs clang (CXX=clang++; Debian packages clang and libclang-rt-14-dev)")
  endif()
  add_compile_options(-fsanitize=fuzzer-no-link)
endif()
