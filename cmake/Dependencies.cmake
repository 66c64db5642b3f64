# Every third-party dependency, found with find_package from Debian 12's packages
# (cmake/apt-packages.txt lists the packages). Found once here; targets link what they use.
find_package(yaml-cpp 0.7 REQUIRED)
find_package(OpenSSL 3 REQUIRED)
find_package(TBB REQUIRED)
find_package(CLI11 2 REQUIRED)
find_package(nlohmann_json 3 REQUIRED)
find_package(Eigen3 3.4 REQUIRED NO_MODULE)
find_package(GTest REQUIRED)
find_package(benchmark REQUIRED)
find_package(OpenMesh REQUIRED)
find_package(CGAL REQUIRED)
find_package(OpenImageIO REQUIRED)
find_package(PNG REQUIRED)
find_package(draco REQUIRED)
find_package(TinyGLTF REQUIRED)
find_package(meshoptimizer REQUIRED)
find_package(assimp REQUIRED)
find_package(OpenGL REQUIRED COMPONENTS OpenGL EGL)
find_package(Threads REQUIRED)

# Debian 12's OpenImageIOTargets.cmake names /usr/include/opencv4 as an include directory of
# OpenImageIO::OpenImageIO even when libopencv-dev is not installed, and CMake refuses to
# generate with a non-existent interface include path. Drop paths that do not exist.
if(TARGET OpenImageIO::OpenImageIO)
  foreach(prop INTERFACE_INCLUDE_DIRECTORIES INTERFACE_SYSTEM_INCLUDE_DIRECTORIES)
    get_target_property(dirs OpenImageIO::OpenImageIO ${prop})
    if(dirs)
      set(kept "")
      foreach(d IN LISTS dirs)
        if(EXISTS "${d}" OR d MATCHES "\\$<")
          list(APPEND kept "${d}")
        endif()
      endforeach()
      set_target_properties(OpenImageIO::OpenImageIO PROPERTIES ${prop} "${kept}")
    endif()
  endforeach()
endif()


# yaml-cpp, libpng (with zlib) and OpenSSL's libcrypto are linked statically into the `sylva`
# binary and dynamically everywhere else: resolving their ~4,700 symbol relocations was most of
# the dynamic loader's time, which every `sylva` process pays before doing anything
# (docs/performance.md, "Engine"). Targets link sylva_yaml / sylva_png / sylva_crypto; the choice
# is made per linking target by its SYLVA_STATIC_DEPS property (set on the binary only, so the
# lazily loaded modules and the tests keep the shared libraries). libstdc++ and oneTBB stay
# shared: the binary and its modules must share one of each.
function(sylva_static_or_shared name shared)
  cmake_parse_arguments(A "" "" "ARCHIVES" ${ARGN})
  set(archives "")
  foreach(a IN LISTS A_ARCHIVES)
    find_library(_sylva_${a} NAMES lib${a}.a NO_CACHE)
    if(NOT _sylva_${a})
      set(archives "")
      break()
    endif()
    list(APPEND archives ${_sylva_${a}})
  endforeach()
  add_library(${name} INTERFACE)
  if(archives)
    add_library(${name}_static INTERFACE)
    target_link_libraries(${name}_static INTERFACE ${archives} ${CMAKE_DL_LIBS} Threads::Threads)
    get_target_property(inc ${shared} INTERFACE_INCLUDE_DIRECTORIES)
    if(inc)
      target_include_directories(${name}_static INTERFACE ${inc})
    endif()
    target_link_libraries(${name} INTERFACE
      "$<IF:$<BOOL:$<TARGET_PROPERTY:SYLVA_STATIC_DEPS>>,${name}_static,${shared}>")
  else()  # no static archive installed: shared everywhere
    target_link_libraries(${name} INTERFACE ${shared})
  endif()
endfunction()
sylva_static_or_shared(sylva_yaml yaml-cpp ARCHIVES yaml-cpp)
sylva_static_or_shared(sylva_png PNG::PNG ARCHIVES png16 z)
sylva_static_or_shared(sylva_crypto OpenSSL::Crypto ARCHIVES crypto)
