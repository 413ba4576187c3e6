# GLSL -> SPIR-V at build time; each shader becomes a header with a uint32_t array that the
# library embeds, so the binary needs no shader files at run time.
set(ISG_SHADER_OUT ${CMAKE_BINARY_DIR}/generated/isg/shaders)
file(MAKE_DIRECTORY ${ISG_SHADER_OUT})

# isg_compile_shaders(TARGET name SOURCES a.comp b.comp ...)
function(isg_compile_shaders)
  cmake_parse_arguments(ARG "" "TARGET" "SOURCES" ${ARGN})
  set(headers)
  foreach(src ${ARG_SOURCES})
    get_filename_component(stem ${src} NAME_WE)
    set(out ${ISG_SHADER_OUT}/${stem}.spv.h)
    file(GLOB deps ${CMAKE_CURRENT_SOURCE_DIR}/*.h ${CMAKE_CURRENT_SOURCE_DIR}/*.glsl)
    add_custom_command(
      OUTPUT ${out}
      COMMAND ${GLSLANG_VALIDATOR} --quiet -V --target-env vulkan1.1 -g0
              -I${CMAKE_CURRENT_SOURCE_DIR} --vn isg_spv_${stem} -o ${out}
              ${CMAKE_CURRENT_SOURCE_DIR}/${src}
      DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/${src} ${deps}
      COMMENT "glslangValidator ${src}"
      VERBATIM)
    list(APPEND headers ${out})
  endforeach()
  add_custom_target(${ARG_TARGET}_spv DEPENDS ${headers})
  add_library(${ARG_TARGET} INTERFACE)
  add_dependencies(${ARG_TARGET} ${ARG_TARGET}_spv)
  target_include_directories(${ARG_TARGET} INTERFACE ${CMAKE_BINARY_DIR}/generated
                                                     ${CMAKE_CURRENT_SOURCE_DIR})
endfunction()
