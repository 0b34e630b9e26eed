# Peak memory of sss-bake against triangles: subdivide_mesh makes the large meshes
# (up to 10M triangles, written to a temporary folder, never committed); memory_sweep.sh runs
# the bakes and draws tests/bench/results/bake/memory.png.
sss_add_benchmark(subdivide_mesh SOURCES ${CMAKE_CURRENT_LIST_DIR}/subdivide_mesh.cpp LIBS sss_mesh)
