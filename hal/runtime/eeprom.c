/* The EEPROM: 4 KiB, erased (0xFF) at the start of every run unless the project keeps it: then the
 * simulator passes its file as the descriptor SEAR_EEPROM_FD_ENV names (lockstep_link.h), which
 * holds this MCU's contents from run to run. A firmware started by hand may name a file in
 * SEAR_EEPROM_FILE instead. Each written byte goes to the file at once, so a run that ends in a
 * crash keeps what the firmware wrote before it, as the chip's cells do. */
#define _POSIX_C_SOURCE 200809L
#include <hal/eeprom.h>

#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "mcu.h"

/* Datasheet (ATmega2560, table 9-2 "EEPROM programming time"): 26368 cycles of the 8 MHz
 * calibrated oscillator, 3.3 ms. */
#define WRITE_NS 3300000

static uint8_t cells[HAL_EEPROM_SIZE];
static int loaded;
static int file = -1;
static int64_t busy_until_ns;

static void load(void) {
  loaded = 1;
  memset(cells, 0xFF, sizeof cells);
  const char *descriptor = getenv(SEAR_EEPROM_FD_ENV);
  const char *path = getenv("SEAR_EEPROM_FILE");
  if (descriptor && *descriptor) {
    file = atoi(descriptor);
    path = "the project's kept EEPROM";
  } else {
    if (!path || !*path) return;
    file = open(path, O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (file < 0) mcu_fatal("EEPROM: cannot open %s, the file SEAR_EEPROM_FILE names", path);
  }
  const ssize_t got = pread(file, cells, sizeof cells, 0);
  /* A new or short file is an erased chip past its end. */
  if (got < (ssize_t)sizeof cells) {
    memset(cells + (got > 0 ? got : 0), 0xFF, sizeof cells - (size_t)(got > 0 ? got : 0));
    if (pwrite(file, cells, sizeof cells, 0) != (ssize_t)sizeof cells) mcu_fatal("EEPROM: cannot write %s", path);
  }
}

static void check(uint16_t address, const char *call) {
  if (address >= HAL_EEPROM_SIZE) mcu_fatal("%s(%u): the ATmega2560's EEPROM holds bytes 0..4095", call, address);
  if (!loaded) load();
}

/* An access waits while a write is still programming, as EEPE stays set. */
static void wait_ready(void) {
  if (busy_until_ns > sear_mcu.link->clock_ns) mcu_advance_to(busy_until_ns);
}

uint8_t eeprom_read(uint16_t address) {
  mcu_enter(SEAR_CALL_eeprom_read);
  check(address, "eeprom_read");
  wait_ready();
  return cells[address];
}

void eeprom_write(uint16_t address, uint8_t value) {
  mcu_enter(SEAR_CALL_eeprom_write);
  check(address, "eeprom_write");
  wait_ready();
  cells[address] = value;
  busy_until_ns = sear_mcu.link->clock_ns + WRITE_NS;
  if (file >= 0 && pwrite(file, &value, 1, address) != 1) mcu_fatal("EEPROM: cannot write byte %u to its file", address);
}
