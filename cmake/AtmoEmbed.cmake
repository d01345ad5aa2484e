# atmo_embed_files(TARGET NAMESPACE BASE_DIR FILES...)
# Compiles text files (GLSL) into the target as a lookup table
#   std::string_view <NAMESPACE>::find(std::string_view relative_path)
# so the plugin needs no files at run time and one GLSL source serves both the
# GPU and the CPU twin (which #includes the same files).
function(atmo_embed_files target namespace base_dir)
  set(files ${ARGN})
  string(REPLACE "::" "_" tag "${namespace}")
  set(out ${CMAKE_CURRENT_BINARY_DIR}/${target}_${tag}_embedded.cpp)
  set(abs_files)
  foreach(f ${files})
    list(APPEND abs_files ${base_dir}/${f})
  endforeach()
  add_custom_command(
    OUTPUT ${out}
    COMMAND ${CMAKE_COMMAND} -DOUT=${out} -DNAMESPACE=${namespace} -DBASE=${base_dir}
            "-DFILES=${files}" -P ${PROJECT_SOURCE_DIR}/cmake/AtmoEmbedScript.cmake
    DEPENDS ${abs_files} ${PROJECT_SOURCE_DIR}/cmake/AtmoEmbedScript.cmake
    COMMENT "Embedding ${namespace} files"
    VERBATIM)
  target_sources(${target} PRIVATE ${out})
endfunction()
