# Mesh loading and baked-PLY writing on the sample dragons (data/fetch.sh).
if(TARGET sss_mesh)
  sss_add_benchmark(bench_mesh SOURCES ${CMAKE_CURRENT_LIST_DIR}/bench_mesh.cpp LIBS sss_mesh)
endif()
