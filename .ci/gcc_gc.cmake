# Included by .ci/test_code_opt.cmake (so after every project() of a `.ci/build`), issue 31: GCC
# collects its own garbage while it compiles, by default whenever its heap has grown by 30 % or
# more past a small floor. Our units peak at about 1 GB of compiler heap, so it collects many
# times for nothing. A floor of ASSISTIVE_GCC_GC_HEAP_KB (4 GB) collects never: measured 6-7 %
# less CPU per unit (pointline_refine.cpp 30.8 s -> 28.6 s, test_slam_fastslam.cpp 12.4 -> 11.6)
# for about 0.2 GB more peak memory, and object files byte for byte the same (the parameters
# tune only the compiler's memory, not what it generates).
set(ASSISTIVE_GCC_GC_HEAP_KB "4194304" CACHE STRING "GCC ggc-min-heapsize in kB, 0 = GCC's default (.ci/gcc_gc.cmake)")
if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND ASSISTIVE_GCC_GC_HEAP_KB)
  add_compile_options("SHELL:--param ggc-min-expand=100" "SHELL:--param ggc-min-heapsize=${ASSISTIVE_GCC_GC_HEAP_KB}")
endif()
