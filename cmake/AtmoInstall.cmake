# AtmoInstall.cmake — what `cmake --install` puts where, the CMake package
# (find_package(Atmo) -> Atmo::host_sdk, Atmo::cigi, Atmo_PLUGIN), the
# pkg-config file and the CPack .deb (docs/INSTALL.md).
#   <prefix>/lib/atmo/libatmo.so, libatmo_vdb.so   the plugin (a host dlopens it; the VDB module must sit
#                                                  next to it: the plugin finds it by its own path)
#   <prefix>/lib/libatmo_host_sdk.a, libatmo_host_cigi.a
#   <prefix>/include/atmo/*.h *.hpp *.glsl         the ABI, the loader, the C++ wrapper, the GLSL includes
#   <prefix>/bin/atmo                              the CLI (finds the plugin at ../lib/atmo)
#   <prefix>/share/atmo/stars, scenarios           the star catalogue `atmo ephemeris` reads; example scenarios
#   <prefix>/lib/cmake/Atmo, lib/pkgconfig/atmo.pc
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(ATMO_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/Atmo)

set_target_properties(atmo_host_sdk PROPERTIES EXPORT_NAME host_sdk)
set_target_properties(atmo_host_cigi PROPERTIES EXPORT_NAME cigi)
set_target_properties(atmo_abi_headers PROPERTIES EXPORT_NAME headers)
install(TARGETS atmo_host_sdk atmo_host_cigi atmo_abi_headers EXPORT AtmoTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/host_sdk/include/atmo DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
  FILES_MATCHING PATTERN "*.h" PATTERN "*.hpp" PATTERN "*.glsl")
install(TARGETS atmo atmo_vdb_module LIBRARY DESTINATION ${ATMO_INSTALL_PLUGINDIR})
install(TARGETS atmo_cli RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(FILES ${PROJECT_SOURCE_DIR}/data/stars/hipparcos_v6_6.tsv DESTINATION ${ATMO_INSTALL_STARDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/config/scenarios/ DESTINATION ${CMAKE_INSTALL_DATADIR}/atmo/scenarios)

install(EXPORT AtmoTargets NAMESPACE Atmo:: DESTINATION ${ATMO_INSTALL_CMAKEDIR})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/package/AtmoConfig.cmake.in
  ${PROJECT_BINARY_DIR}/package/AtmoConfig.cmake
  INSTALL_DESTINATION ${ATMO_INSTALL_CMAKEDIR}
  PATH_VARS ATMO_INSTALL_PLUGINDIR CMAKE_INSTALL_INCLUDEDIR)
write_basic_package_version_file(${PROJECT_BINARY_DIR}/package/AtmoConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)  # 0.x: a minor version may break the SDK's C++ parts
install(FILES ${PROJECT_BINARY_DIR}/package/AtmoConfig.cmake ${PROJECT_BINARY_DIR}/package/AtmoConfigVersion.cmake
  DESTINATION ${ATMO_INSTALL_CMAKEDIR})
string(REGEX REPLACE "[^/]+" ".." ATMO_PC_UP "${CMAKE_INSTALL_LIBDIR}/pkgconfig")  # pkgconfig dir -> prefix
set(ATMO_PC_LIBS "-ldl")
if(ATMO_SANITIZE)
  string(APPEND ATMO_PC_LIBS " -fsanitize=address,undefined")  # the static library is instrumented
endif()
configure_file(${PROJECT_SOURCE_DIR}/cmake/package/atmo.pc.in ${PROJECT_BINARY_DIR}/package/atmo.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/package/atmo.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)

# `cpack -G DEB` in the build folder: one package, its run-time dependencies
# found by dpkg-shlibdeps from what the binaries link.
set(CPACK_PACKAGE_NAME atmo)
set(CPACK_PACKAGE_VENDOR "Atmo")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "Atmosphere layer of an image generator: sky, aerial perspective, clouds, night sky, fog (plugin, host SDK, CLI)")
set(CPACK_PACKAGE_CONTACT "Atmo developers <atmo@localhost>")
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION graphics)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_PACKAGE_FILE_NAME_NO_ARCH ON)
include(CPack)
