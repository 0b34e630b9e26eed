# The accuracy study of issue 5 (tests/bench/accuracy_study.sh runs it and draws the charts).
if(TARGET sss_pathtrace AND TARGET sss_bake)
  sss_add_benchmark(accuracy_study SOURCES ${CMAKE_CURRENT_SOURCE_DIR}/accuracy_study.cpp
                    LIBS sss_pathtrace sss_bake sss_mesh sss_material sss_envmap)
endif()
