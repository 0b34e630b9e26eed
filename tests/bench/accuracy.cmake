# The accuracy study (tests/bench/accuracy_study.sh runs it and draws the charts).
sss_add_benchmark(accuracy_study SOURCES ${CMAKE_CURRENT_LIST_DIR}/accuracy_study.cpp
                  LIBS sss_pathtrace sss_bench_guard sss_bake sss_mesh sss_material sss_envmap)
# The sun study against the forward light tracer (sun-lit spheres, a back-lit slab).
sss_add_benchmark(sun_study SOURCES ${CMAKE_CURRENT_LIST_DIR}/sun_study.cpp
                  LIBS sss_pathtrace sss_bake sss_mesh sss_material sss_envmap)
# The concavity study: interreflection against the forward light tracer (a box with a pit).
sss_add_benchmark(concavity_study SOURCES ${CMAKE_CURRENT_LIST_DIR}/concavity_study.cpp
                  LIBS sss_pathtrace sss_bake sss_mesh sss_material sss_envmap)
# A volumetric path tracer's cost at the bake's error (tests/bench/pathtracer_cost.sh).
sss_add_benchmark(pathtracer_cost SOURCES ${CMAKE_CURRENT_LIST_DIR}/pathtracer_cost.cpp
                  LIBS sss_pathtrace sss_bake sss_mesh sss_material sss_envmap)
# The material-interface study: a sphere of two materials against a Monte Carlo of both media.
sss_add_benchmark(material_interface_study
                  SOURCES ${CMAKE_CURRENT_LIST_DIR}/material_interface_study.cpp
                  LIBS sss_bake sss_mesh sss_material sss_envmap nlohmann_json::nlohmann_json)
# The exit-model study: one-material spheres under uniform light, the radiance along the normal per
# channel against a Monte Carlo that tallies it directly.
sss_add_benchmark(exit_model_study SOURCES ${CMAKE_CURRENT_LIST_DIR}/exit_model_study.cpp
                  LIBS sss_bake sss_mesh sss_material sss_envmap)
