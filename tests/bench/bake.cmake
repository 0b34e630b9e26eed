# The whole sss-bake pipeline on the sample dragons (data/fetch.sh): bake_bench (Google Benchmark:
# the 100K-vertex dragon, stage times and peak memory) and bake_sweep (methods x tolerances x
# resolutions, CSV). bake_sweep.sh runs both and draws tests/bench/results/bake/*.png.
sss_add_benchmark(bake_bench SOURCES ${CMAKE_CURRENT_LIST_DIR}/bake_bench.cpp
                  LIBS sss_bake sss_mesh sss_envmap nlohmann_json::nlohmann_json)
sss_add_benchmark(bake_sweep SOURCES ${CMAKE_CURRENT_LIST_DIR}/bake_sweep.cpp
                  LIBS sss_bake sss_mesh sss_envmap sss_material)
# The texture bake (--texture) on a low-poly UV sphere against a dense per-vertex bake:
# tests/bench/results/texture/sphere.csv.
sss_add_benchmark(texture_study SOURCES ${CMAKE_CURRENT_LIST_DIR}/texture_study.cpp
                  LIBS sss_bake sss_lightmap sss_mesh nlohmann_json::nlohmann_json)
# The relightable bake against fresh bakes under the sample HDRs turned and a sun from 8 directions:
# tests/bench/results/relight/relight.csv, relight_cost.csv (relight_study.sh).
sss_add_benchmark(relight_study SOURCES ${CMAKE_CURRENT_LIST_DIR}/relight_study.cpp
                  LIBS sss_bake sss_mesh sss_envmap sss_material)
