# `make deb` (cpack -G DEB in the build tree): three Debian packages from the install components
# (cmake/install.cmake), installed under /usr:
#   tagbench           runtime: libtagbench.so.SOVERSION, the tagbench program, the family files
#   libtagbench-dev    dev: headers, libtagbench.so and .a, CMake package, pkg-config files
#   python3-tagbench   python: the module in /usr/lib/python3/dist-packages
# Shared-library dependencies (libopencv-*, libapriltag3, libc6, ...) come from dpkg-shlibdeps; the
# ones it cannot see are named here. test_deb_contents (examples/tests) checks the packages.
set(CPACK_PACKAGE_NAME tagbench)
set(CPACK_PACKAGE_VENDOR "tagbench")
set(CPACK_PACKAGE_CONTACT "tagbench maintainers <tagbench@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "AprilTag detector of the 2011 paper, tag families and the benchmark harness")
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_GENERATOR DEB)
set(CPACK_DEB_COMPONENT_INSTALL ON)
set(CPACK_COMPONENTS_ALL runtime dev)
if(TARGET tagbench_python)
  list(APPEND CPACK_COMPONENTS_ALL python)
endif()
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)

set(CPACK_DEBIAN_RUNTIME_PACKAGE_NAME tagbench)
set(CPACK_DEBIAN_RUNTIME_DESCRIPTION "AprilTag detector library and the tagbench program\n The detector of the 2011 AprilTag paper (libtagbench), the tagbench command-line\n program (detect, render, families, benchmarks) and the shipped tag families.")
set(CPACK_DEBIAN_DEV_PACKAGE_NAME libtagbench-dev)
set(CPACK_DEBIAN_DEV_PACKAGE_SECTION libdevel)
set(CPACK_DEBIAN_DEV_DESCRIPTION "AprilTag detector library: development files\n Public headers <tagbench/...>, static library, CMake package (find_package(tagbench))\n and pkg-config files (tagbench, tagbench-opencv).")
# The headers include Eigen's; <tagbench/opencv.hpp> OpenCV's.
set(CPACK_DEBIAN_DEV_PACKAGE_DEPENDS "tagbench (= ${PROJECT_VERSION}), libeigen3-dev (>= 3.4), libopencv-dev (>= 4.6)")
set(CPACK_DEBIAN_PYTHON_PACKAGE_NAME python3-tagbench)
set(CPACK_DEBIAN_PYTHON_PACKAGE_SECTION python)
set(CPACK_DEBIAN_PYTHON_DESCRIPTION "AprilTag detector: Python 3 module\n import tagbench: Detector(...).detect(numpy uint8 image), families, rendering.")
# The module is built for one Python minor version (its file name says which).
set(CPACK_DEBIAN_PYTHON_PACKAGE_DEPENDS
    "python3 (>= ${TAGBENCH_PYTHON_VERSION}), python3 (<< ${TAGBENCH_PYTHON_NEXT_VERSION}), python3-numpy")
include(CPack)
