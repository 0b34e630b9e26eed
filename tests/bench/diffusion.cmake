# The diffusion sums of Li & Guo Eq. 7: diffusion_bench (methods x tolerances on the dragons;
# diffusion_sweep.sh runs it and draws tests/bench/results/diffusion/*.png) and
# diffusion_resolution (the same sums across mesh resolutions).
sss_add_benchmark(diffusion_bench SOURCES ${CMAKE_CURRENT_LIST_DIR}/diffusion_bench.cpp
                  LIBS sss_bake sss_mesh sss_material)
sss_add_benchmark(diffusion_resolution SOURCES ${CMAKE_CURRENT_LIST_DIR}/diffusion_resolution.cpp
                  LIBS sss_bake sss_mesh sss_material)
