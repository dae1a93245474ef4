# install.cmake: what `cmake --install build --prefix P` puts under P, and the Debian package
# `cpack -G DEB` (run in the build folder) makes of the same files. The program finds its data
# relative to itself (engine/core/install.h), so the tree works wherever it is copied:
#   P/bin/roger
#   P/share/roger/{scenarios,curricula,scripts}   the Lua libraries, shipped scenarios and scripts
#   P/share/roger/web                             the pages (also compiled into roger)
#   P/share/roger/api, .luarc.json, .luacheckrc   the Lua API for editors and the linter (docs/authoring.md)
#   P/share/doc/roger                             README.md and docs/, examples included
install(TARGETS roger RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(DIRECTORY scenarios curricula scripts DESTINATION ${CMAKE_INSTALL_DATADIR}/roger
        USE_SOURCE_PERMISSIONS PATTERN "__pycache__" EXCLUDE)
install(DIRECTORY engine/view/web/ engine/report/web/ DESTINATION ${CMAKE_INSTALL_DATADIR}/roger/web)
install(DIRECTORY api DESTINATION ${CMAKE_INSTALL_DATADIR}/roger)
install(FILES .luarc.json .luacheckrc DESTINATION ${CMAKE_INSTALL_DATADIR}/roger)
install(FILES README.md DESTINATION ${CMAKE_INSTALL_DOCDIR})
install(DIRECTORY docs/ DESTINATION ${CMAKE_INSTALL_DOCDIR})

set(CPACK_PACKAGE_NAME roger)
set(CPACK_PACKAGE_VENDOR "roger")
set(CPACK_PACKAGE_CONTACT "roger maintainers <roger@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
    "Simulated mobile manipulator learning skills by developmental curricula (Lua-scripted)")
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
# The shared libraries roger links (Lua, Box2D, cairo, PLplot...) become the package's Depends.
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
# PLplot loads its cairo driver at run time, which shlibdeps cannot see.
set(CPACK_DEBIAN_PACKAGE_DEPENDS "plplot-driver-cairo")
# The Python module (docs/python.md), when built: `import roger` needs numpy, which the program does
# not, so it is recommended rather than required; scripts/dqn.py's deep learner needs torch.
# gymnasium, whose checker and wrappers judge the module, is not packaged by Debian bookworm (pip).
if(ROGER_PYTHON_BUILD)
  set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "python3-numpy")
  set(CPACK_DEBIAN_PACKAGE_SUGGESTS "python3-torch")
endif()
include(CPack)
