# install.cmake - what `cmake --install` puts where (GNUInstallDirs), the man
# page made from --help for it, and the Debian package (`cpack -G DEB`)
# made from the same rules. Included by the top CMakeLists.txt.
include(GNUInstallDirs)

# The man page: the program's own --help, turned into roff at build time, so
# that the two cannot drift apart (the help's layout is the contract:
# cmake/help2man.awk).
set(RT_MAN_PAGE ${PROJECT_BINARY_DIR}/rt-mpi.1)
add_custom_command(
  OUTPUT ${RT_MAN_PAGE}
  COMMAND sh -c "\"$1\" --help >\"$4.help\" && awk -v version=\"$2\" -f \"$3\" \"$4.help\" >\"$4.tmp\" && mv \"$4.tmp\" \"$4\""
          sh $<TARGET_FILE:rt-mpi> ${PROJECT_VERSION} ${PROJECT_SOURCE_DIR}/cmake/help2man.awk ${RT_MAN_PAGE}
  DEPENDS rt-mpi ${PROJECT_SOURCE_DIR}/cmake/help2man.awk
  COMMENT "Generating the man page rt-mpi.1 from rt-mpi --help"
  VERBATIM)
add_custom_target(man ALL DEPENDS ${RT_MAN_PAGE})

install(TARGETS rt-mpi RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(FILES ${RT_MAN_PAGE} DESTINATION ${CMAKE_INSTALL_MANDIR}/man1)
# share/rt-mpi: the example scenes and the Slurm batch script.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/scenes/ DESTINATION ${CMAKE_INSTALL_DATADIR}/rt-mpi/scenes)
install(PROGRAMS ${PROJECT_SOURCE_DIR}/scripts/slurm/rt-mpi.sbatch DESTINATION ${CMAKE_INSTALL_DATADIR}/rt-mpi/slurm)
# The user documentation (the notes under docs/notes are the developers').
install(FILES ${PROJECT_SOURCE_DIR}/README.md ${PROJECT_SOURCE_DIR}/docs/SCENES_AND_FORMATS.md
              ${PROJECT_SOURCE_DIR}/docs/SCALING.md ${PROJECT_SOURCE_DIR}/docs/PERFORMANCE.md
        DESTINATION ${CMAKE_INSTALL_DOCDIR})
install(FILES ${PROJECT_SOURCE_DIR}/docker/README.md DESTINATION ${CMAKE_INSTALL_DOCDIR} RENAME CONTAINERS.md)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/docs/images DESTINATION ${CMAKE_INSTALL_DOCDIR})

# The Debian package: `cpack -G DEB` in the build directory writes
# rt-mpi_<version>_<arch>.deb. dpkg-shlibdeps finds the libraries the binary
# links (Open MPI, libpng, libgomp, cJSON, OpenEXR, libjpeg: whichever this build
# has); mpirun is a program, not a library, so openmpi-bin is named here.
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME rt-mpi)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "distributed path tracer (MPI + OpenMP) for the Ray Tracing in One Weekend scenes")
set(CPACK_PACKAGE_DESCRIPTION "rt-mpi renders the book's scenes, or JSON scene files, across MPI ranks \
and OpenMP threads; the image is byte-identical for any number of ranks and threads. Checkpoints \
survive Slurm time limits; an example batch script is in /usr/share/rt-mpi/slurm.")
set(CPACK_PACKAGE_CONTACT "rt-mpi developers")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_STRIP_FILES ON)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION graphics)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
if(RT_MPI)
  set(CPACK_DEBIAN_PACKAGE_DEPENDS "openmpi-bin")
endif()
include(CPack)
