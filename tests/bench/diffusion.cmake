# The diffusion sums of Eq. 7: methods x tolerances on the dragons (diffusion_sweep.sh runs it and
# draws tests/bench/results/diffusion/*.png).
if(TARGET sss_bake AND TARGET sss_mesh)
  sss_add_benchmark(diffusion_bench SOURCES ${CMAKE_CURRENT_LIST_DIR}/diffusion_bench.cpp
                    LIBS sss_bake sss_mesh sss_material)
endif()
if(TARGET sss_bake AND TARGET sss_mesh)
  sss_add_benchmark(diffusion_resolution SOURCES ${CMAKE_CURRENT_LIST_DIR}/diffusion_resolution.cpp
                    LIBS sss_bake sss_mesh sss_material)
endif()
