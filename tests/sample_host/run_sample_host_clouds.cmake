cmake_policy(SET CMP0054 NEW)  # quoted arguments of if() are strings
# ctest -P script: the same headless frame without clouds and with CLOUD_ARGS
# (a ,-list of options, e.g. --cloud,cumulus:4:1200:2500:5:7), compared with
# `atmo compare` (ATMO): the clouds must change the frame, PSNR below
# MAX_PSNR_DB (identical frames give inf; llvmpipe draws the same frame twice
# bit for bit).
file(REMOVE_RECURSE ${OUT_DIR})
string(REPLACE "," ";" cloud_options "${CLOUD_ARGS}")
set(common --plugin ${PLUGIN} --frames 1 --width 256 --height 144)
foreach(run clear with_clouds)
  if(run STREQUAL "with_clouds")
    set(extra ${cloud_options})
  else()
    set(extra)
  endif()
  execute_process(COMMAND ${SAMPLE_HOST} ${common} --out ${OUT_DIR}/${run} ${extra}
                  RESULT_VARIABLE result OUTPUT_VARIABLE output ERROR_VARIABLE output)
  message(STATUS "${run}: ${output}")
  if(NOT result EQUAL 0)
    message(FATAL_ERROR "atmo-sample-host (${run}) exited with ${result}")
  endif()
endforeach()
if(NOT output MATCHES "set_clouds: 1 layer")
  message(FATAL_ERROR "the clouds run did not report set_clouds")
endif()
execute_process(COMMAND ${ATMO} compare ${OUT_DIR}/with_clouds/frame_000.png ${OUT_DIR}/clear/frame_000.png
                RESULT_VARIABLE result OUTPUT_VARIABLE compared ERROR_VARIABLE compared)
message(STATUS "${compared}")
if(NOT result EQUAL 0 OR NOT compared MATCHES "PSNR ([0-9.]+) dB")
  message(FATAL_ERROR "atmo compare failed (${result}) or printed no finite PSNR: the frames are identical?")
endif()
set(psnr ${CMAKE_MATCH_1})
if(NOT psnr LESS MAX_PSNR_DB)
  message(FATAL_ERROR "with clouds vs without: PSNR ${psnr} dB >= ${MAX_PSNR_DB} dB: the clouds did not change the frame")
endif()
message(STATUS "with clouds vs without: PSNR ${psnr} dB < ${MAX_PSNR_DB} dB")
