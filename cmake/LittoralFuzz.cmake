# The fuzz targets (fuzz/) need clang and libFuzzer, so they are a separate CMake project, built
# here as an external project into build/fuzz whenever the main build runs. With tests enabled,
# each target gets a CTest smoke run of LITTORAL_FUZZ_SMOKE_SECONDS from its seed corpus (label
# "fuzz"); the long campaign is fuzz/campaign.sh (docs/reliability.md).
find_program(LITTORAL_FUZZ_CXX NAMES clang++-14 clang++)
if(NOT LITTORAL_FUZZ_CXX)
  message(FATAL_ERROR "LITTORAL_FUZZ needs clang++ with libFuzzer (Debian: clang libclang-rt-14-dev, installed by "
                      "scripts/setup-deps.sh), or configure with -DLITTORAL_FUZZ=OFF")
endif()
include(ExternalProject)
set(LITTORAL_FUZZ_JOBS 2 CACHE STRING "Parallel jobs of the fuzz-target build")
set(LITTORAL_FUZZ_TARGETS scene ir ply obj off stl raster soundings spectrum_csv checkpoint tile_checkpoint)
if(LITTORAL_FUZZ_RENDER)
  list(APPEND LITTORAL_FUZZ_TARGETS ir_render)
endif()
ExternalProject_Add(littoral_fuzz
  SOURCE_DIR ${PROJECT_SOURCE_DIR}/fuzz
  BINARY_DIR ${PROJECT_BINARY_DIR}/fuzz
  # -O0 with line tables only: the smoke runs need coverage and the sanitizers, not speed (libFuzzer
  # runs every seed before it watches the clock, so a slower build still replays the whole seed
  # corpus), and a crash's stack still names file and line. This compiles in half the time of -O1
  # (scene_ir.cpp: 16 against 33 CPU-s; -O1 took 3/4 of -O2 -g's); the long campaign builds
  # fuzz/ itself, with its default -O2 -g.
  CMAKE_ARGS -DCMAKE_CXX_COMPILER=${LITTORAL_FUZZ_CXX} -DCMAKE_BUILD_TYPE=RelWithDebInfo
             "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O0 -gline-tables-only -DNDEBUG"
             -DLITTORAL_FUZZ_RENDER=${LITTORAL_FUZZ_RENDER}
  BUILD_COMMAND ${CMAKE_COMMAND} --build <BINARY_DIR> -j${LITTORAL_FUZZ_JOBS}
  INSTALL_COMMAND ""
  BUILD_ALWAYS ON
  USES_TERMINAL_BUILD OFF)
if(LITTORAL_BUILD_TESTS)
  foreach(t ${LITTORAL_FUZZ_TARGETS})
    set(_dict "")
    if(EXISTS ${PROJECT_SOURCE_DIR}/fuzz/${t}.dict)
      set(_dict -dict=${PROJECT_SOURCE_DIR}/fuzz/${t}.dict)
    endif()
    add_test(NAME fuzz_smoke.${t}
             COMMAND ${PROJECT_SOURCE_DIR}/fuzz/smoke.sh ${PROJECT_BINARY_DIR}/fuzz/fuzz_${t}
                     ${PROJECT_SOURCE_DIR}/fuzz/corpus/${t} ${PROJECT_BINARY_DIR}/fuzz/smoke/${t}
                     ${LITTORAL_FUZZ_SMOKE_SECONDS} ${_dict})
    set_tests_properties(fuzz_smoke.${t} PROPERTIES LABELS fuzz TIMEOUT 300)
  endforeach()
endif()
