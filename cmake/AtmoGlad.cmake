# Generates the GL loader at build time with Debian's glad (python3-glad,
# glad 2): GL 4.5 core plus the few extensions the plugin may use. No internal
# loader (--loader off): the plugin loads entry points through the host's
# proc-address function, so it links neither libGL nor libEGL.
find_program(ATMO_GLAD_EXECUTABLE glad PATHS /usr/bin NO_DEFAULT_PATH)
if(NOT ATMO_GLAD_EXECUTABLE)
  find_program(ATMO_GLAD_EXECUTABLE glad REQUIRED)
endif()

set(_glad_dir ${CMAKE_BINARY_DIR}/generated/glad)
add_custom_command(
  OUTPUT ${_glad_dir}/src/gl.c ${_glad_dir}/include/glad/gl.h
  COMMAND ${ATMO_GLAD_EXECUTABLE} --quiet --reproducible
          --api gl:core=4.5
          --extensions GL_KHR_debug,GL_ARB_clip_control
          --out-path ${_glad_dir} c
  COMMENT "Generating the GL loader with glad"
  VERBATIM)
add_library(atmo_glad STATIC ${_glad_dir}/src/gl.c)
target_include_directories(atmo_glad SYSTEM PUBLIC ${_glad_dir}/include)
set_target_properties(atmo_glad PROPERTIES C_VISIBILITY_PRESET hidden POSITION_INDEPENDENT_CODE ON)
