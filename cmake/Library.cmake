# The installable library (docs/library.md): libdecalcomp, shared and static, built from the same
# position-independent objects as the internal layers (geometry, core, io), with the frame
# pipeline's public headers, a CMake package (decalcompConfig.cmake, targets decalcomp::decalcomp
# and decalcomp::decalcomp_static) and a pkg-config file. Internal headers are not installed.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(DECALCOMP_LAYERS decalcomp_geometry decalcomp_core decalcomp_io)
set_target_properties(${DECALCOMP_LAYERS} PROPERTIES POSITION_INDEPENDENT_CODE ON)

# The public API: the frame pipeline (frame.hpp, batch.hpp, pipeline.hpp), the compositor and its
# device, scenes, cameras, masks, profiles, provenance and what they include. tests/install checks that every
# installed header compiles on its own against the installed tree.
set(DECALCOMP_PUBLIC_HEADERS
  bake batch beauty camera camera_solve channel_mapping compositor contact_sheet cryptomatte decal depth_check device error
  exr_chunks exr_file frame frame_beauty frame_pattern gbuffer gbuffer_exr masks normal_check pipeline
  pixel_filter profiles provenance rest_mesh scene sequence_conventions shard)
list(TRANSFORM DECALCOMP_PUBLIC_HEADERS PREPEND ${CMAKE_SOURCE_DIR}/include/decalcomp/)
list(TRANSFORM DECALCOMP_PUBLIC_HEADERS APPEND .hpp)

set(DECALCOMP_LAYER_OBJECTS)
foreach(layer ${DECALCOMP_LAYERS})
  list(APPEND DECALCOMP_LAYER_OBJECTS $<TARGET_OBJECTS:${layer}>)
endforeach()

# What the compiled objects need at link time; only OpenCL, OpenEXR (Imath) and GLM reach the
# public headers.
set(DECALCOMP_PUBLIC_DEPENDENCIES decalcomp_opencl_public OpenEXR::OpenEXR glm::glm)
set(DECALCOMP_PRIVATE_DEPENDENCIES OpenEXR::OpenEXRCore OpenImageIO::OpenImageIO tinyobjloader::tinyobjloader fmt::fmt
    OpenMP::OpenMP_CXX Threads::Threads deflate)

# decalcomp_opencl without the build tree's own target name: the same definitions, exported.
add_library(decalcomp_opencl_public INTERFACE)
target_compile_definitions(decalcomp_opencl_public INTERFACE
  CL_HPP_TARGET_OPENCL_VERSION=120 CL_HPP_MINIMUM_OPENCL_VERSION=120 CL_HPP_ENABLE_EXCEPTIONS
  CL_TARGET_OPENCL_VERSION=120)
target_link_libraries(decalcomp_opencl_public INTERFACE OpenCL::OpenCL)
set_target_properties(decalcomp_opencl_public PROPERTIES EXPORT_NAME opencl)

foreach(kind shared static)
  set(target decalcomp_library_${kind})
  string(TOUPPER ${kind} type)
  add_library(${target} ${type} ${DECALCOMP_LAYER_OBJECTS})
  add_dependencies(${target} ${DECALCOMP_LAYERS})
  target_include_directories(${target} PUBLIC
    $<BUILD_INTERFACE:${CMAKE_SOURCE_DIR}/include> $<BUILD_INTERFACE:${DECALCOMP_GENERATED_INCLUDE}>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_link_libraries(${target} PUBLIC ${DECALCOMP_PUBLIC_DEPENDENCIES} PRIVATE ${DECALCOMP_PRIVATE_DEPENDENCIES})
  set_target_properties(${target} PROPERTIES OUTPUT_NAME decalcomp)
endforeach()
set_target_properties(decalcomp_library_shared PROPERTIES
  EXPORT_NAME decalcomp VERSION ${PROJECT_VERSION} SOVERSION ${PROJECT_VERSION_MAJOR})
set_target_properties(decalcomp_library_static PROPERTIES EXPORT_NAME decalcomp_static)

install(TARGETS decalcomp_library_shared decalcomp_opencl_public EXPORT decalcompTargets
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR} ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(TARGETS decalcomp_library_static EXPORT decalcompStaticTargets ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
# OpenImageIO's module (src/images/image_codecs.hpp), found by the CLI and libdecalcomp.so relative
# to themselves, and by programs linking libdecalcomp.a at this path or $DECALCOMP_IMAGE_MODULE.
install(TARGETS decalcomp_images LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}/decalcomp)
install(FILES ${DECALCOMP_PUBLIC_HEADERS} ${DECALCOMP_GENERATED_INCLUDE}/decalcomp/version.hpp
  DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/decalcomp)
install(TARGETS decalcomp RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})

set(DECALCOMP_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/decalcomp)
install(EXPORT decalcompTargets NAMESPACE decalcomp:: DESTINATION ${DECALCOMP_CMAKE_DIR})
install(EXPORT decalcompStaticTargets NAMESPACE decalcomp:: DESTINATION ${DECALCOMP_CMAKE_DIR})
configure_package_config_file(${CMAKE_SOURCE_DIR}/cmake/package/decalcompConfig.cmake.in
  ${CMAKE_BINARY_DIR}/package/decalcompConfig.cmake INSTALL_DESTINATION ${DECALCOMP_CMAKE_DIR})
# 0.x: minor versions may change the API, so only the same minor satisfies a request.
write_basic_package_version_file(${CMAKE_BINARY_DIR}/package/decalcompConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_BINARY_DIR}/package/decalcompConfig.cmake ${CMAKE_BINARY_DIR}/package/decalcompConfigVersion.cmake
  DESTINATION ${DECALCOMP_CMAKE_DIR})

file(RELATIVE_PATH DECALCOMP_PC_TO_PREFIX /${CMAKE_INSTALL_LIBDIR}/pkgconfig /)
configure_file(${CMAKE_SOURCE_DIR}/cmake/package/decalcomp.pc.in ${CMAKE_BINARY_DIR}/package/decalcomp.pc @ONLY)
install(FILES ${CMAKE_BINARY_DIR}/package/decalcomp.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
