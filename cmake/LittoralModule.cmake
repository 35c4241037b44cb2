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
