# cmake --install into a fresh temporary prefix, then build and run a small host outside the tree against
# it: with find_package(Atmo) (CMake) and with pkg-config (a plain cc line). -P script; inputs:
#   BUILD_DIR (the Atmo build tree), WORK (a scratch folder, emptied), HOST_SRC (tests/install/host),
#   C_COMPILER, SANITIZE (ON in the sanitizer build: the static SDK is instrumented).
foreach(v BUILD_DIR WORK HOST_SRC C_COMPILER)
  if(NOT DEFINED ${v})
    message(FATAL_ERROR "run_install_test.cmake: ${v} is not set")
  endif()
endforeach()
file(REMOVE_RECURSE ${WORK})
set(prefix ${WORK}/prefix)

function(run what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 600)
  message(STATUS "${what}:\n${out}${err}")
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${what} failed (${rc})")
  endif()
  set(last_output "${out}" PARENT_SCOPE)
endfunction()

run("cmake --install" ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})
foreach(f include/atmo/atmo.h include/atmo/atmo.hpp include/atmo/atmo_loader.h include/atmo/atmo_geodetic.h
          include/atmo/cigi.h include/atmo/atmo_sky_occlusion.glsl lib/libatmo_host_sdk.a lib/libatmo_host_cigi.a
          lib/atmo/libatmo.so lib/atmo/libatmo_vdb.so bin/atmo lib/cmake/Atmo/AtmoConfig.cmake
          lib/cmake/Atmo/AtmoConfigVersion.cmake lib/pkgconfig/atmo.pc share/atmo/stars/hipparcos_v6_6.tsv
          share/atmo/scenarios/noon_clear.json)
  if(NOT EXISTS ${prefix}/${f})
    message(FATAL_ERROR "the install has no ${f}")
  endif()
endforeach()

# find_package(Atmo) from a CMake project outside the tree.
run("configure the host" ${CMAKE_COMMAND} -S ${HOST_SRC} -B ${WORK}/host-build -DCMAKE_PREFIX_PATH=${prefix}
    -DCMAKE_C_COMPILER=${C_COMPILER})
file(READ ${WORK}/host-build/plugin_path.txt plugin)
if(NOT plugin STREQUAL "${prefix}/lib/atmo/libatmo.so")
  message(FATAL_ERROR "Atmo_PLUGIN is '${plugin}', not the installed plugin ${prefix}/lib/atmo/libatmo.so")
endif()
run("build the host" ${CMAKE_COMMAND} --build ${WORK}/host-build)
run("the host (find_package)" ${WORK}/host-build/atmo-installed-host ${plugin})
run("the CIGI host (find_package)" ${WORK}/host-build/atmo-installed-cigi)

# pkg-config: the same C host from one compiler line; the plugin's path from the .pc file.
set(ENV{PKG_CONFIG_PATH} ${prefix}/lib/pkgconfig)
run("pkg-config" pkg-config --cflags --libs atmo)
separate_arguments(flags UNIX_COMMAND "${last_output}")
run("pkg-config plugin" pkg-config --variable=plugin atmo)
string(STRIP "${last_output}" pc_plugin)
run("cc with pkg-config" ${C_COMPILER} -std=c99 -Wall -Wextra -Werror ${HOST_SRC}/host.c -o ${WORK}/host-pc ${flags} -lm)
run("the host (pkg-config)" ${WORK}/host-pc ${pc_plugin})

# Relocatable: the prefix moved after installing still serves pkg-config and the CLI.
file(RENAME ${prefix} ${WORK}/moved)
set(prefix ${WORK}/moved)
set(ENV{PKG_CONFIG_PATH} ${prefix}/lib/pkgconfig)
run("pkg-config plugin (moved prefix)" pkg-config --variable=plugin atmo)
string(STRIP "${last_output}" pc_plugin)
if(NOT EXISTS ${pc_plugin})
  message(FATAL_ERROR "after moving the prefix, pkg-config names '${pc_plugin}', which does not exist")
endif()
run("the host (pkg-config, moved prefix)" ${WORK}/host-pc ${pc_plugin})

# The installed CLI finds the installed plugin and catalogue by itself (no --plugin).
run("installed atmo ephemeris" ${prefix}/bin/atmo ephemeris --lat 47.46 --lon 8.56 --utc 2024-06-21T11:00:00Z)
message(STATUS "install test passed: ${prefix}")
