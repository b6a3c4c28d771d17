# Cross-compiling for the Arduino Mega 2560 (ATmega2560 at 16 MHz) with Debian's gcc-avr.
# Use: cmake -S . -B build-avr -DCMAKE_TOOLCHAIN_FILE=cmake/avr-gcc.cmake
set(CMAKE_SYSTEM_NAME Generic)
set(CMAKE_SYSTEM_PROCESSOR avr)

find_program(AVR_GCC avr-gcc REQUIRED)
find_program(AVR_GXX avr-g++ REQUIRED)
find_program(AVR_OBJCOPY avr-objcopy REQUIRED)
find_program(AVR_SIZE avr-size REQUIRED)
set(CMAKE_C_COMPILER ${AVR_GCC})
set(CMAKE_CXX_COMPILER ${AVR_GXX})
set(CMAKE_OBJCOPY ${AVR_OBJCOPY} CACHE FILEPATH "")

set(SEAR_AVR_MCU atmega2560)
set(SEAR_AVR_F_CPU 16000000UL)
# Each function and object in its own section, so that --gc-sections drops what a firmware
# never calls: flash is 256 KiB and RAM 8 KiB.
set(CMAKE_C_FLAGS_INIT "-mmcu=${SEAR_AVR_MCU} -DF_CPU=${SEAR_AVR_F_CPU} -Os -ffunction-sections -fdata-sections")
set(CMAKE_CXX_FLAGS_INIT "${CMAKE_C_FLAGS_INIT}")
set(CMAKE_EXE_LINKER_FLAGS_INIT "-mmcu=${SEAR_AVR_MCU} -Wl,--gc-sections")
# The build types' own -O2/-O3 would come after -Os and win; firmware is always built for size.
foreach(lang C CXX)
  set(CMAKE_${lang}_FLAGS_DEBUG_INIT "-Og -g")
  set(CMAKE_${lang}_FLAGS_RELEASE_INIT "-Os -DNDEBUG")
  set(CMAKE_${lang}_FLAGS_RELWITHDEBINFO_INIT "-Os -g -DNDEBUG")
  set(CMAKE_${lang}_FLAGS_MINSIZEREL_INIT "-Os -DNDEBUG")
endforeach()

# avr-libc's headers and libraries are found by the compiler itself; nothing of the host's.
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)
