# Finds Hemirad's Debian-packaged dependencies; a missing one is a configure error naming its package.
include(FindPkgConfig)

function(hemirad_require found package)
  if(NOT ${found})
    message(FATAL_ERROR "Hemirad: missing dependency; install the Debian package '${package}' "
                        "(scripts/install-deps.sh installs everything)")
  endif()
endfunction()

find_package(Eigen3 3.3 QUIET NO_MODULE)
hemirad_require(Eigen3_FOUND libeigen3-dev)

if(HEMIRAD_WITH_EMBREE)
  find_package(embree 3 QUIET)
  hemirad_require(embree_FOUND libembree-dev)
endif()

find_package(OpenMP QUIET COMPONENTS CXX)
hemirad_require(OpenMP_CXX_FOUND "g++ (libgomp)")

find_package(Threads REQUIRED)

find_path(HEMIRAD_STB_INCLUDE stb/stb_image_write.h)
hemirad_require(HEMIRAD_STB_INCLUDE libstb-dev)

if(HEMIRAD_WITH_OPENGL)
  pkg_check_modules(HEMIRAD_EGL QUIET IMPORTED_TARGET egl)
  hemirad_require(HEMIRAD_EGL_FOUND "libegl-dev")
  pkg_check_modules(HEMIRAD_OSMESA QUIET IMPORTED_TARGET osmesa)
  hemirad_require(HEMIRAD_OSMESA_FOUND "libosmesa6-dev")
  find_path(HEMIRAD_GLCOREARB_INCLUDE GL/glcorearb.h)
  hemirad_require(HEMIRAD_GLCOREARB_INCLUDE "libgl-dev")
endif()

if(HEMIRAD_WITH_GUI)
  pkg_check_modules(HEMIRAD_GLFW QUIET IMPORTED_TARGET glfw3)
  hemirad_require(HEMIRAD_GLFW_FOUND "libglfw3-dev")
  pkg_check_modules(HEMIRAD_IMGUI QUIET IMPORTED_TARGET imgui)
  hemirad_require(HEMIRAD_IMGUI_FOUND "libimgui-dev")
endif()

if(HEMIRAD_WITH_MPI)
  find_package(MPI QUIET COMPONENTS CXX)
  hemirad_require(MPI_CXX_FOUND "libopenmpi-dev")
  find_program(HEMIRAD_MPIEXEC NAMES mpirun mpiexec HINTS ${MPI_HOME} PATH_SUFFIXES bin)
  hemirad_require(HEMIRAD_MPIEXEC "openmpi-bin")
  pkg_check_modules(HEMIRAD_PETSC QUIET IMPORTED_TARGET PETSc)
  hemirad_require(HEMIRAD_PETSC_FOUND "petsc-dev")
endif()

if(HEMIRAD_WITH_PYTHON)
  # Debian's python3-numpy and friends belong to Debian's interpreter, whatever python3 comes first on
  # PATH (pyenv, conda); -DPython3_EXECUTABLE=... picks another (pip install . passes its own).
  if(NOT Python3_EXECUTABLE AND EXISTS /usr/bin/python3)
    set(Python3_EXECUTABLE /usr/bin/python3)
  endif()
  find_package(Python3 QUIET COMPONENTS Interpreter Development.Module)
  hemirad_require(Python3_FOUND "python3-dev")
  find_package(pybind11 2.6 QUIET CONFIG)
  hemirad_require(pybind11_FOUND pybind11-dev)
  foreach(module numpy scipy)
    execute_process(COMMAND ${Python3_EXECUTABLE} -c "import ${module}" RESULT_VARIABLE missing OUTPUT_QUIET ERROR_QUIET)
    if(missing)
      hemirad_require(FALSE "python3-${module}")
    endif()
  endforeach()
endif()

if(HEMIRAD_WITH_TESTS)
  find_package(doctest QUIET)
  hemirad_require(doctest_FOUND doctest-dev)
endif()
