# Every third-party dependency of jaderender, found once, from Debian 12 packages.
# All are found now, including those only later parts of the pipeline use, so the
# shape of the build is settled. Order matters: OpenVDB's Find module folder also
# holds FindTBB/FindOpenEXR modules, so the CONFIG packages come first.

find_package(TBB CONFIG REQUIRED)
find_package(Imath CONFIG REQUIRED)
find_package(OpenEXR CONFIG REQUIRED)
find_package(OpenImageIO CONFIG REQUIRED)
find_package(embree 3 CONFIG REQUIRED)
find_package(glm CONFIG REQUIRED)
find_package(TinyGLTF CONFIG REQUIRED)
find_package(tinyobjloader CONFIG REQUIRED)
find_package(CLI11 CONFIG REQUIRED)
find_package(nlohmann_json CONFIG REQUIRED)
find_package(Catch2 2 CONFIG REQUIRED)

# OpenVDB ships only a Find module, in its own folder.
list(APPEND CMAKE_MODULE_PATH /usr/lib/x86_64-linux-gnu/cmake/OpenVDB)
find_package(OpenVDB REQUIRED)

# OpenCV's core (its DFT, for texture spectra). Debian's libopencv-core-dev
# ships no CMake config of its own, so the library is found by name.
find_path(JADE_OPENCV_INCLUDE_DIR opencv2/core.hpp PATH_SUFFIXES opencv4 REQUIRED)
find_library(JADE_OPENCV_CORE_LIBRARY opencv_core REQUIRED)
add_library(OpenCV::core UNKNOWN IMPORTED)
set_target_properties(OpenCV::core PROPERTIES
  IMPORTED_LOCATION ${JADE_OPENCV_CORE_LIBRARY}
  INTERFACE_INCLUDE_DIRECTORIES ${JADE_OPENCV_INCLUDE_DIR})
