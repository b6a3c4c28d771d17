/* simavr on its own, as the reference for the AVR engine's speed: an AVR image run on libsimavr's
 * ATmega2560 with avr_run() and nothing else (no lockstep, no devices, no profile), for a number
 * of cycles, timed on the host's clock. Its simulated MHz per second is what this host gives
 * simavr's decoder at the moment; bench/avr_engine_rtf.sh prints it beside the engine's, so that
 * the engine's speed can be read against the host's. As in the engine, the CPU never sleeps on
 * the host's clock, disabled level-triggered external interrupts are not polled (simavr #465),
 * and the timers' phase-correct modes are defined (engines/avr/timer_modes.c): left undefined,
 * simavr 1.6 raises interrupt flags every 64 cycles and this would measure that, not its decoder.
 *
 * Usage: simavr_bare_bench IMAGE.elf [CYCLES]   (default 160e6, 10 s at 16 MHz) */
#define _POSIX_C_SOURCE 200809L
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include <avr_extint.h>
#include <sim_avr.h>
#include <sim_elf.h>

#include "engine.h"

static void no_sleep(avr_t *avr, avr_cycle_count_t how_long) {
  (void)avr;
  (void)how_long;
}

int main(int argc, char **argv) {
  if (argc < 2) {
    fprintf(stderr, "usage: simavr_bare_bench IMAGE.elf [CYCLES]\n");
    return 2;
  }
  const uint64_t cycles = argc > 2 ? (uint64_t)strtod(argv[2], NULL) : 160000000u;
  static elf_firmware_t firmware;
  if (elf_read_firmware(argv[1], &firmware) != 0) {
    fprintf(stderr, "simavr_bare_bench: cannot read %s\n", argv[1]);
    return 1;
  }
  avr_t *avr = avr_make_mcu_by_name("atmega2560");
  if (!avr) return 1;
  avr_init(avr);
  avr_load_firmware(avr, &firmware);
  avr->frequency = 16000000u;
  avr->sleep = no_sleep;
  avr->log = LOG_NONE;
  for (uint8_t n = 0; n < 8; ++n) avr_extint_set_strict_lvl_trig(avr, n, 0);
  if (avr_timer_modes_define(avr) != 6) return 1;
  struct timespec start, end;
  clock_gettime(CLOCK_MONOTONIC, &start);
  int state = cpu_Running;
  while (avr->cycle < cycles && (state == cpu_Running || state == cpu_Sleeping)) state = avr_run(avr);
  clock_gettime(CLOCK_MONOTONIC, &end);
  const double seconds = (double)(end.tv_sec - start.tv_sec) + (double)(end.tv_nsec - start.tv_nsec) * 1e-9;
  if (state != cpu_Running && state != cpu_Sleeping) {
    fprintf(stderr, "simavr_bare_bench: the image stopped at cycle %" PRIu64 " (state %d)\n", (uint64_t)avr->cycle, state);
    return 1;
  }
  printf("%.1f\n", (double)avr->cycle / seconds / 1e6);
  return 0;
}
