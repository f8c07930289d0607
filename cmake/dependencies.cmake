# Every outside package sylva uses is found here, and only here. All come from
# Debian 12 packages (scripts/debian-packages.txt, installed by the README's
# commands through scripts/common.sh); nothing is downloaded at configure time.

# TBB must come first: OpenVDB's bundled FindTBB would otherwise define a
# partial TBB::tbb target that breaks the packages found after it.
find_package(TBB CONFIG REQUIRED)
find_package(Threads REQUIRED)
find_package(Eigen3 3.4 REQUIRED NO_MODULE)
find_package(nlohmann_json 3.10 REQUIRED)
find_package(OpenImageIO REQUIRED)
# PNG, read and written directly (core/io/png_codec.h): libpng 1.6 (libpng-dev).
find_package(PNG 1.6 REQUIRED)

# OpenVDB ships a find module, not a config file; it needs Boost.Iostreams.
list(APPEND CMAKE_MODULE_PATH /usr/lib/x86_64-linux-gnu/cmake/OpenVDB)
find_package(OpenVDB REQUIRED)

find_package(embree 3.13 REQUIRED)

# glTF export (mesh/gltf_export.cc). Debian ships tinygltf as a shared
# library with a CMake config (target TinyGLTF::TinyGLTF).
find_package(TinyGLTF CONFIG REQUIRED)

# Matting (reconstruct/matting): OpenCV 4.6 core + imgproc, and the alphamat
# contrib module (libopencv-contrib-dev) for information-flow matting; livewire
# (reconstruct/attractors) also uses ximgproc's thinning (same package).
find_package(OpenCV 4.6 REQUIRED COMPONENTS core imgproc alphamat ximgproc)

# Loose / manual registration (reconstruct/registration): Ceres 2.1. Found
# after TBB (see above) so its exported targets see the full TBB::tbb.
find_package(Ceres 2.1 REQUIRED)

# SVG stroke files (sketch/strokes.cc): tinyxml2 9 (libtinyxml2-dev), whose
# CMake config defines the imported target tinyxml2::tinyxml2.
find_package(tinyxml2 9 CONFIG REQUIRED)

# The desktop app (ui/desktop): Qt 6.4 Widgets, and QTest for its tests
# (qt6-base-dev). Optional: SYLVA_BUILD_GUI defaults to ON only when found.
# Only ui/desktop links Qt.
find_package(Qt6 COMPONENTS Widgets Test QUIET)
# Its optional OpenGL 3D view (ui/desktop/view_3d_gl.cc): Qt's OpenGL and
# OpenGL widgets modules (libqt6opengl6-dev); built when found.
find_package(Qt6 COMPONENTS OpenGL OpenGLWidgets QUIET)

if(SYLVA_BUILD_TESTS)
  find_package(GTest REQUIRED)
  find_package(benchmark REQUIRED)
endif()
