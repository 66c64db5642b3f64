# Use ccache when it is present (it is in cmake/apt-packages.txt, but a build without it works).
find_program(SYLVA_CCACHE ccache)
if(SYLVA_CCACHE AND NOT CMAKE_CXX_COMPILER_LAUNCHER)
  set(CMAKE_CXX_COMPILER_LAUNCHER "${SYLVA_CCACHE}")
endif()
