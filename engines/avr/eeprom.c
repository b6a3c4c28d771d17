/* The ATmega2560's EEPROM kept from run to run when the project asks (<eeprom persist="true">):
 * the file the simulator passes (SEAR_EEPROM_FD_ENV) goes into simavr's EEPROM before the chip
 * starts, and what the firmware changed goes back to it at every hand-over, so that whatever the
 * chip wrote before the simulator let go of it is in the file. */
#define _GNU_SOURCE
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <avr_eeprom.h>
#include <sim_avr.h>

#include "engine.h"

#define EEPROM_BYTES 4096 /* ATmega2560 datasheet, 8.3: 4K bytes */

static int file = -1;
static uint8_t saved[EEPROM_BYTES]; /* what the file holds */

static void chip_cells(uint8_t *into) {
  avr_eeprom_desc_t desc = {.ee = into, .offset = 0, .size = EEPROM_BYTES};
  avr_ioctl(engine.avr, AVR_IOCTL_EEPROM_GET, &desc);
}

void avr_eeprom_load(void) {
  const char *descriptor = getenv(SEAR_EEPROM_FD_ENV);
  if (!descriptor || !*descriptor) return;
  /* The chip as loaded (erased, with the image's .eeprom section), the file's bytes over it: a
   * new or short file keeps the image's initial contents past its end. */
  uint8_t cells[EEPROM_BYTES];
  chip_cells(cells);
  const int fd = atoi(descriptor);
  const ssize_t got = pread(fd, cells, sizeof cells, 0);
  if (got < 0) engine_fatal("cannot read the project's kept EEPROM: %s", strerror(errno));
  avr_eeprom_desc_t desc = {.ee = cells, .offset = 0, .size = EEPROM_BYTES};
  avr_ioctl(engine.avr, AVR_IOCTL_EEPROM_SET, &desc);
  chip_cells(saved);
  if (memcmp(saved, cells, sizeof cells) != 0) engine_fatal("libsimavr did not take the kept EEPROM's contents");
  if (got < (ssize_t)sizeof cells && pwrite(fd, cells, sizeof cells, 0) != (ssize_t)sizeof cells)
    engine_fatal("cannot write the project's kept EEPROM: %s", strerror(errno));
  file = fd;
}

void avr_eeprom_save(void) {
  if (file < 0) return;
  uint8_t cells[EEPROM_BYTES];
  chip_cells(cells);
  size_t first = 0, end = sizeof cells;
  while (first < end && cells[first] == saved[first]) ++first;
  if (first == end) return;
  while (cells[end - 1] == saved[end - 1]) --end;
  if (pwrite(file, cells + first, end - first, (off_t)first) != (ssize_t)(end - first)) {
    file = -1; /* engine_fatal saves too */
    engine_fatal("cannot write the project's kept EEPROM: %s", strerror(errno));
  }
  memcpy(saved + first, cells + first, end - first);
}
