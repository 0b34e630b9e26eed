# Profiles and their Gaussian fits: fit speed (Google Benchmark) and the tables/charts of
# tests/bench/results/material (material_charts.sh runs material_profiles and gnuplot).
sss_add_benchmark(material_bench SOURCES ${CMAKE_CURRENT_LIST_DIR}/material_bench.cpp
                  LIBS sss_material)
sss_add_benchmark(material_profiles SOURCES ${CMAKE_CURRENT_LIST_DIR}/material_profiles.cpp
                  LIBS sss_material)
# Regenerates lib/material/halfspace_albedo_table.cpp (minutes): material_albedo_table OUT.cpp
sss_add_benchmark(material_albedo_table
                  SOURCES ${CMAKE_CURRENT_LIST_DIR}/material_albedo_table.cpp LIBS sss_material)
