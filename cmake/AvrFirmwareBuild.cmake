# In the host build: also cross-build every firmware example for the ATmega2560, as a nested
# build in <build>/avr with cmake/avr-gcc.cmake, so that each host build shows the examples'
# avr-size whenever they relink. -DSEAR_AVR=OFF leaves it out.
option(SEAR_AVR "Also build the firmware examples for the ATmega2560 (needs gcc-avr, avr-libc, binutils-avr)" ON)

if(SEAR_AVR)
  find_program(SEAR_AVR_GCC avr-gcc)
  if(NOT SEAR_AVR_GCC)
    message(FATAL_ERROR "SEAR_AVR is ON but avr-gcc is missing: run scripts/install-deps.sh "
                        "(gcc-avr avr-libc binutils-avr) or configure with -DSEAR_AVR=OFF")
  endif()
  get_filename_component(_sear_avr_source "${CMAKE_CURRENT_LIST_DIR}/.." ABSOLUTE)
  include(ExternalProject)
  ExternalProject_Add(sear_avr_firmware
    SOURCE_DIR ${_sear_avr_source}
    BINARY_DIR ${CMAKE_BINARY_DIR}/avr
    CMAKE_ARGS -DCMAKE_TOOLCHAIN_FILE=${_sear_avr_source}/cmake/avr-gcc.cmake
    INSTALL_COMMAND ""
    # ExternalProject cannot see the nested build's sources; its own make decides what is stale.
    BUILD_ALWAYS ON
    USES_TERMINAL_BUILD ON)
endif()
