# Read by cpack for each generator (CPACK_PROJECT_CONFIG_FILE, CMakeLists.txt). Without
# dpkg-shlibdeps and file CPack writes a .deb that depends on nothing: stop instead.
if(CPACK_GENERATOR STREQUAL "DEB")
  foreach(program IN ITEMS dpkg-shlibdeps file)
    find_program(SSS_${program} ${program})
    if(NOT SSS_${program})
      message(FATAL_ERROR "cpack -G DEB needs ${program}: "
                          "apt-get install --no-install-recommends dpkg-dev file")
    endif()
  endforeach()
endif()
