# sear_add_firmware() for the AVR cross build (cmake/avr-gcc.cmake): each firmware becomes
# NAME.elf linked against sear_hal_avr, NAME.hex for the programmer, and an avr-size report.
include_guard(GLOBAL)

# The warnings a firmware is held to; not -Werror, so a new compiler's warning never stops a
# build that the board would run.
set(SEAR_FIRMWARE_WARNINGS -Wall -Wextra -Wpedantic -Wconversion)

# sear_add_firmware(name SOURCES a.c b.c ...)
function(sear_add_firmware name)
  cmake_parse_arguments(PARSE_ARGV 1 FW "" "" "SOURCES")
  if(NOT FW_SOURCES)
    message(FATAL_ERROR "sear_add_firmware(${name}): no SOURCES given")
  endif()
  if(FW_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR "sear_add_firmware(${name}): unexpected arguments ${FW_UNPARSED_ARGUMENTS}")
  endif()

  set(dir ${CMAKE_CURRENT_BINARY_DIR})
  add_executable(${name} ${FW_SOURCES})
  # The same C dialect as the simulator build of the same source (cmake/SearFirmwareSim.cmake).
  set_target_properties(${name} PROPERTIES
    SUFFIX ".elf" RUNTIME_OUTPUT_DIRECTORY ${dir} C_STANDARD 99 C_EXTENSIONS OFF)
  target_compile_options(${name} PRIVATE ${SEAR_FIRMWARE_WARNINGS})
  target_link_libraries(${name} PRIVATE sear_hal_avr)
  target_link_options(${name} PRIVATE "LINKER:-Map=${dir}/${name}.map")

  add_custom_command(TARGET ${name} POST_BUILD
    COMMAND ${CMAKE_OBJCOPY} -O ihex -R .eeprom ${dir}/${name}.elf ${dir}/${name}.hex
    COMMAND ${AVR_SIZE} --format=avr --mcu=${SEAR_AVR_MCU} ${dir}/${name}.elf
    BYPRODUCTS ${dir}/${name}.hex ${dir}/${name}.map
    COMMENT "${name}: ${name}.hex and its size on the ${SEAR_AVR_MCU}"
    VERBATIM)
endfunction()
