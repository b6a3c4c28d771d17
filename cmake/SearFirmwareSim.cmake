# sear_add_firmware(name SOURCES a.c b.c ...): a firmware as an ordinary executable with its own
# main(), linked against the simulator's HAL. A user's own firmware tree that add_subdirectory()s
# SEAR builds the same way; the AVR build defines the same function for the real chip.
function(sear_add_firmware name)
  cmake_parse_arguments(FW "" "" "SOURCES" ${ARGN})
  if(NOT FW_SOURCES)
    message(FATAL_ERROR "sear_add_firmware(${name}) needs SOURCES")
  endif()
  add_executable(${name} ${FW_SOURCES})
  set_target_properties(${name} PROPERTIES C_STANDARD 99 C_EXTENSIONS OFF)
  target_compile_options(${name} PRIVATE -Wall -Wextra -Wpedantic -Wconversion)
  target_link_libraries(${name} PRIVATE sear_hal_sim)
endfunction()
