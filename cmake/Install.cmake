# What `cmake --install` places beyond the executables (each target installs itself) and the
# Debian package (issue 55): man pages, bash completion, the docs and the bundled sample; then
# `cpack -G DEB` -> isg_<version>_amd64.deb.

# Man pages from the binaries' --help by help2man (Debian's help2man), at build time.
find_program(HELP2MAN help2man)
if(HELP2MAN)
  set(man_dir ${PROJECT_BINARY_DIR}/man)
  set(isg_subs run info compare devices presets params roofline farm farm:submit farm:status)
  add_custom_command(OUTPUT ${man_dir}/isg.1
    COMMAND ${CMAKE_COMMAND} -E make_directory ${man_dir}
    COMMAND ${CMAKE_COMMAND} -DHELP2MAN=${HELP2MAN} -DBIN=$<TARGET_FILE_DIR:isg> -DPROG=isg
            "-DNAME=soft shadows, glossy reflections and depth of field from a renderer's AOVs"
            "-DSUBS=${isg_subs}" -DEXTRA=${PROJECT_SOURCE_DIR}/docs/man/isg.h2m
            -DOUT=${man_dir}/isg.1 -P ${PROJECT_SOURCE_DIR}/cmake/Manpage.cmake
    DEPENDS isg ${PROJECT_SOURCE_DIR}/docs/man/isg.h2m ${PROJECT_SOURCE_DIR}/cmake/Manpage.cmake
    COMMENT "man page isg.1" VERBATIM)
  add_custom_command(OUTPUT ${man_dir}/isg-synth.1
    COMMAND ${CMAKE_COMMAND} -E make_directory ${man_dir}
    COMMAND ${CMAKE_COMMAND} -DHELP2MAN=${HELP2MAN} -DBIN=$<TARGET_FILE_DIR:isg-synth> -DPROG=isg-synth
            "-DNAME=ground-truth AOVs and ray-traced references for isg" -DSUBS=
            -DEXTRA=${PROJECT_SOURCE_DIR}/docs/man/isg-synth.h2m
            -DOUT=${man_dir}/isg-synth.1 -P ${PROJECT_SOURCE_DIR}/cmake/Manpage.cmake
    DEPENDS isg-synth ${PROJECT_SOURCE_DIR}/docs/man/isg-synth.h2m ${PROJECT_SOURCE_DIR}/cmake/Manpage.cmake
    COMMENT "man page isg-synth.1" VERBATIM)
  add_custom_target(isg_man ALL DEPENDS ${man_dir}/isg.1 ${man_dir}/isg-synth.1)
  install(FILES ${man_dir}/isg.1 ${man_dir}/isg-synth.1 ${PROJECT_SOURCE_DIR}/docs/man/isg-exrcheck.1
          DESTINATION share/man/man1)
else()
  message(STATUS "man pages: not built (needs help2man)")
endif()

install(FILES ${PROJECT_SOURCE_DIR}/cli/share/isg.bash-completion
        DESTINATION share/bash-completion/completions RENAME isg)
install(FILES ${PROJECT_SOURCE_DIR}/README.md DESTINATION share/doc/isg)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/docs/ DESTINATION share/doc/isg PATTERN man EXCLUDE)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/samples/ DESTINATION share/isg/samples)

# The Debian package. Its dependencies come from the binaries' shared libraries
# (dpkg-shlibdeps), plus what they load at run time: a Vulkan driver, the Python the module was
# built for, and NumPy, which the module's arrays are.
set(CPACK_PACKAGE_NAME isg)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_CONTACT "isg developers <isg@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "soft shadows, glossy reflections and depth of field from a renderer's AOVs")
set(CPACK_PACKAGE_DESCRIPTION "isg reads a renderer's EXR AOVs and writes soft shadows, glossy
reflections and depth of field, as Vulkan compute passes, with a composited EXR. Includes the
isg-synth ground-truth generator and the Python module (import isg).")
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_STRIP_FILES ON)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION graphics)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(isg_deb_depends "mesa-vulkan-drivers | vulkan-icd")
if(ISG_PYTHON_DEB_DEPENDS)
  string(APPEND isg_deb_depends ", ${ISG_PYTHON_DEB_DEPENDS}")
endif()
set(CPACK_DEBIAN_PACKAGE_DEPENDS "${isg_deb_depends}")
set(CPACK_DEBIAN_PACKAGE_HOMEPAGE "https://localhost/isg")
include(CPack)
