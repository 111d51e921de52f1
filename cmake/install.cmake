# What `cmake --install` (and `make install PREFIX=...`, `make deb`) puts where, by component:
#   runtime  lib/libtagbench.so.SOVERSION, bin/tagbench, share/tagbench/families/*.fam
#   dev      include/tagbench/ (the public headers, the generated version.hpp, and detail/: the stage
#            headers the public ones include), lib/libtagbench.{so,a}, lib/cmake/tagbench/,
#            lib/pkgconfig/tagbench{,-opencv}.pc
#   python   TAGBENCH_PYTHON_INSTALL_DIR/tagbench.*.so (python/CMakeLists.txt)
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(TAGBENCH_FAMILY_INSTALL_DIR ${CMAKE_INSTALL_DATADIR}/tagbench/families)
set(TAGBENCH_CMAKE_INSTALL_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/tagbench)
set(TAGBENCH_PC_INSTALL_DIR ${CMAKE_INSTALL_LIBDIR}/pkgconfig)

install(TARGETS tagbench_shared EXPORT tagbench-targets
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT runtime NAMELINK_COMPONENT dev)
install(TARGETS tagbench_core EXPORT tagbench-static-targets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT dev)
install(TARGETS tagbench_opencv EXPORT tagbench-opencv-targets COMPONENT dev)
install(TARGETS tagbench RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT runtime)

file(GLOB TAGBENCH_SHIPPED_FAMILIES ${PROJECT_SOURCE_DIR}/detector/codes/families/*.fam)
install(FILES ${TAGBENCH_SHIPPED_FAMILIES} DESTINATION ${TAGBENCH_FAMILY_INSTALL_DIR} COMPONENT runtime)

# Headers: the public facade, the generated version header, and under tagbench/detail/ the stage
# headers it includes (they include each other by file-relative paths, so PREFIX/include is the one
# include directory a user needs). The list is the facade's closure: a test
# (test_install_headers) checks that each public header compiles alone from the install.
install(FILES include/tagbench/detector.hpp include/tagbench/family.hpp include/tagbench/opencv.hpp
              include/tagbench/tagbench.hpp ${TAGBENCH_GENERATED_INCLUDE}/tagbench/version.hpp
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/tagbench COMPONENT dev)
foreach(h codes/bits.hpp codes/hamming_scan.hpp codes/tag_family.hpp codes/families.hpp codes/tag_layout.hpp
          detect/detector.hpp detect/detector_options.hpp detect/detector_opencv.hpp detect/image.hpp detect/line_fit.hpp
          detect/payload_decode.hpp detect/payload_area.hpp detect/pose.hpp detect/quad_search.hpp
          detect/segmentation.hpp detect/gradient.hpp detect/homography.hpp detect/threshold_quads.hpp
          detect/threshold.hpp detect/components.hpp detect/boundaries.hpp detect/angle_order.hpp detect/quad_fit.hpp
          detect/edge_refine.hpp detect/quad_fit_occluded.hpp detect/occlusion_refit.hpp detect/linear_corners.hpp detect/photometric_refine.hpp
          detect/outer_outline.hpp detect/second_look.hpp detect/group_look.hpp detect/printed_square.hpp detect/ring_quads.hpp detect/line_quads.hpp detect/coarse_pass.hpp detect/dark_outlines.hpp detect/line_segments.hpp detect/soft_decode.hpp detect/low_contrast_quads.hpp detect/bent_decode.hpp detect/code_refit.hpp detect/corner_completion.hpp detect/defocus_read.hpp detect/border_kink.hpp detect/photometric_guard.hpp
          detect/pose_choice.hpp)
  get_filename_component(dir ${h} DIRECTORY)
  install(FILES detector/${h} DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/tagbench/detail/${dir} COMPONENT dev)
endforeach()

install(EXPORT tagbench-targets NAMESPACE tagbench:: DESTINATION ${TAGBENCH_CMAKE_INSTALL_DIR} COMPONENT dev)
install(EXPORT tagbench-static-targets NAMESPACE tagbench:: DESTINATION ${TAGBENCH_CMAKE_INSTALL_DIR} COMPONENT dev)
install(EXPORT tagbench-opencv-targets NAMESPACE tagbench:: DESTINATION ${TAGBENCH_CMAKE_INSTALL_DIR} COMPONENT dev)
configure_package_config_file(cmake/tagbench-config.cmake.in ${PROJECT_BINARY_DIR}/tagbench-config.cmake
  INSTALL_DESTINATION ${TAGBENCH_CMAKE_INSTALL_DIR} PATH_VARS TAGBENCH_FAMILY_INSTALL_DIR)
# 0.x: a minor version may break the API, so only the same MAJOR.MINOR is compatible.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/tagbench-config-version.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/tagbench-config.cmake ${PROJECT_BINARY_DIR}/tagbench-config-version.cmake
        DESTINATION ${TAGBENCH_CMAKE_INSTALL_DIR} COMPONENT dev)

# pkg-config files, relocatable: prefix is found from the .pc file's own place (${pcfiledir}).
file(RELATIVE_PATH TAGBENCH_PC_TO_PREFIX /prefix/${TAGBENCH_PC_INSTALL_DIR} /prefix)
foreach(pc tagbench tagbench-opencv)
  configure_file(cmake/${pc}.pc.in ${PROJECT_BINARY_DIR}/${pc}.pc @ONLY)
  install(FILES ${PROJECT_BINARY_DIR}/${pc}.pc DESTINATION ${TAGBENCH_PC_INSTALL_DIR} COMPONENT dev)
endforeach()
