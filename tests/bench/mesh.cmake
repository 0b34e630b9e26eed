# Mesh loading and baked-PLY writing on the sample dragons (data/fetch.sh).
sss_add_benchmark(mesh_bench SOURCES ${CMAKE_CURRENT_LIST_DIR}/mesh_bench.cpp LIBS sss_mesh)
