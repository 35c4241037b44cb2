# littoral_module(<name>): one library per module folder, built from every .cpp in the folder
# (so a concept is added as a .h/.cpp pair without touching CMake), exported as littoral::<name>,
# with includes rooted at the repository. A folder with no sources yet still configures.
function(littoral_module name)
  file(GLOB sources CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/*.cpp)
  if(NOT sources)
    configure_file(${PROJECT_SOURCE_DIR}/core/empty_unit.cpp.in ${CMAKE_CURRENT_BINARY_DIR}/empty_unit.cpp COPYONLY)
    set(sources ${CMAKE_CURRENT_BINARY_DIR}/empty_unit.cpp)
  endif()
  add_library(littoral_${name} ${sources})
  add_library(littoral::${name} ALIAS littoral_${name})
  target_include_directories(littoral_${name} PUBLIC ${PROJECT_SOURCE_DIR})
endfunction()

# littoral_cold_sources(file...): code that reads and writes small text files (the Scene IR's JSON,
# the scene file's YAML) or glues the commands together spends its build time in the optimiser and
# its run time elsewhere, so optimised builds compile it at -O1 (the Scene IR: 24 -> 18 CPU-s; a
# unity file of the commands: 30 -> 18). A file belongs here only if none of its loops runs per
# ray, photon, sample, pixel or mesh element. Call it in the folder whose target compiles the files.
set(LITTORAL_COLD_OPT "$<$<CONFIG:Release,RelWithDebInfo,MinSizeRel>:-O1>")
function(littoral_cold_sources)
  set_source_files_properties(${ARGN} PROPERTIES COMPILE_OPTIONS "${LITTORAL_COLD_OPT}")
endfunction()
