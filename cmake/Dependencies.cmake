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

