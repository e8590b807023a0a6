# pgt's shipped files, found beside the binary at run time (src/core/data_dir.h):
#   build tree: build/share/pgt/{shaders,analysis,scenes,docs} link to the sources, so a
#               build runs as it is;
#   install:    PREFIX/bin/pgt, PREFIX/share/pgt/..., PREFIX/lib/python3/dist-packages/pgt;
#   package:    `cpack -G DEB` in the build folder makes pgt_VERSION_amd64.deb (prefix /usr).
set(PGT_DATA_ENTRIES "analysis=analysis" "scenes=scenes" "docs=docs" "README.md=README.md")
# Each entry once: linked into the build tree, installed as NAME under share/pgt.
set(PGT_SHARE ${CMAKE_INSTALL_DATADIR}/pgt)
file(MAKE_DIRECTORY ${PROJECT_BINARY_DIR}/share/pgt)
foreach(entry ${PGT_DATA_ENTRIES})
  string(REPLACE "=" ";" pair ${entry})
  list(GET pair 0 name)
  list(GET pair 1 source)
  set(from ${PROJECT_SOURCE_DIR}/${source})
  file(CREATE_LINK ${from} ${PROJECT_BINARY_DIR}/share/pgt/${name} SYMBOLIC)
  if(IS_DIRECTORY ${from})
    install(DIRECTORY ${from}/ DESTINATION ${PGT_SHARE}/${name} PATTERN "__pycache__" EXCLUDE)
  else()
    install(FILES ${from} DESTINATION ${PGT_SHARE})
  endif()
endforeach()

# The shaders: the built-ins' GLSL beside their C++ kernels (src/methods/builtin) and the
# engine presets' beside their table (src/methods/presets), gathered as shaders/ and
# shaders/presets/ (names scenes use: pgt:layered.glsl, pgt:presets/godot.glsl). In the build
# tree each file is linked; CONFIGURE_DEPENDS picks up a new one.
foreach(pair "builtin;" "presets;presets/")
  list(GET pair 0 folder)
  list(LENGTH pair n)
  set(sub "")
  if(n GREATER 1)
    list(GET pair 1 sub)
  endif()
  file(GLOB glsl CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/src/methods/${folder}/*.glsl)
  file(MAKE_DIRECTORY ${PROJECT_BINARY_DIR}/share/pgt/shaders/${sub})
  foreach(file ${glsl})
    get_filename_component(name ${file} NAME)
    file(CREATE_LINK ${file} ${PROJECT_BINARY_DIR}/share/pgt/shaders/${sub}${name} SYMBOLIC)
  endforeach()
  install(FILES ${glsl} DESTINATION ${PGT_SHARE}/shaders/${sub})
endforeach()

# The .deb: Debian's runtime libraries found by dpkg-shlibdeps (package dpkg-dev), plus what
# pgt runs beside itself: Debian's python3 with the report's packages, Mesa's EGL and GL.
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME pgt)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
    "Parallax Ground Truth: how wrong parallax mapping is, against the traced displaced surface")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEBIAN_PACKAGE_MAINTAINER "pgt developers <pgt@localhost>")
set(CPACK_DEBIAN_PACKAGE_SECTION graphics)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_DEPENDS
    "python3, python3-numpy, python3-pandas, python3-matplotlib, libegl-mesa0, libgl1-mesa-dri, fonts-dejavu-core")
include(CPack)
