# Irradiance speed (Google Benchmark) and the methods x sizes sweep behind the error-versus-time
# chart (irradiance_sweep.sh runs both and draws tests/bench/results/irradiance/*.png).
sss_add_benchmark(irradiance_bench SOURCES ${CMAKE_CURRENT_LIST_DIR}/irradiance_bench.cpp
                  LIBS sss_irradiance sss_envmap)
sss_add_benchmark(irradiance_sweep SOURCES ${CMAKE_CURRENT_LIST_DIR}/irradiance_sweep.cpp
                  LIBS sss_irradiance sss_envmap)
# sss-irrmap against cmft (irrmap_vs_cmft.sh): DDS input, error against the exact sum, batch.
sss_add_benchmark(irrmap_compare SOURCES ${CMAKE_CURRENT_LIST_DIR}/irrmap_compare.cpp
                  LIBS sss_irradiance sss_envmap)
