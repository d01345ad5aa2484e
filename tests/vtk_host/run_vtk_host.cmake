# ctest -P script: renders FRAMES frames of atmo-vtk-host with the plugin
# (ARGS, a ,-list of more options) and with --no-atmo under xvfb-run -a (VTK
# 9.1 on Debian is GLX only), each into a clean folder, and runs the image
# check on the last frame of each. The host's exit status covers GL errors,
# GL state changes and VTK state-cache mismatches after every plugin call.
string(REPLACE "," ";" extra "${ARGS}")
set(common --plugin ${PLUGIN} --frames ${FRAMES} --width ${WIDTH} --height ${HEIGHT})
# -f: an auth file of our own, so xvfb-run makes and removes no temporary folder
# (its clean-up of that folder fails now and then: "problem while cleaning up
# temporary directory", exit 5, whatever the command's status).
file(MAKE_DIRECTORY ${OUT_DIR})
foreach(run atmo plain)
  file(REMOVE_RECURSE ${OUT_DIR}/${run})
  if(run STREQUAL "atmo")
    set(options ${extra})
  else()
    set(options ${extra} --no-atmo)
  endif()
  execute_process(
    COMMAND ${XVFB_RUN} -a -f ${OUT_DIR}/Xauthority ${HOST} ${common} --out ${OUT_DIR}/${run} ${options}
    RESULT_VARIABLE result TIMEOUT 120)
  if(NOT result EQUAL 0)
    message(FATAL_ERROR "atmo-vtk-host (${run}: ${options}) exited with '${result}'")
  endif()
endforeach()
math(EXPR last "${FRAMES} - 1")
string(LENGTH "${last}" digits)
math(EXPR pad "4 - ${digits}")
string(REPEAT "0" ${pad} zeros)
execute_process(
  COMMAND ${CHECK} ${OUT_DIR}/atmo ${OUT_DIR}/plain vtk_host_${zeros}${last}.png
  RESULT_VARIABLE result)
if(NOT result EQUAL 0)
  message(FATAL_ERROR "vtk_host_image_check failed (${result})")
endif()
