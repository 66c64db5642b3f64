# Warnings for sylva's own targets (third-party headers are included as SYSTEM and stay quiet).
add_library(sylva_warnings INTERFACE)
target_compile_options(sylva_warnings INTERFACE -Wall -Wextra -Wpedantic $<$<CXX_COMPILER_ID:GNU>:-Wshadow=local>
                                                -Wnon-virtual-dtor -Wimplicit-fallthrough)
option(SYLVA_WERROR "treat warnings as errors" OFF)
if(SYLVA_WERROR)
  target_compile_options(sylva_warnings INTERFACE -Werror)
endif()
# Sanitizer preset: cmake -DSYLVA_SANITIZE=address,undefined
set(SYLVA_SANITIZE "" CACHE STRING "comma-separated -fsanitize= list")
if(SYLVA_SANITIZE)
  add_compile_options(-fsanitize=${SYLVA_SANITIZE} -fno-omit-frame-pointer)
  add_link_options(-fsanitize=${SYLVA_SANITIZE})
endif()
