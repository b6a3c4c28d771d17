/* What the AVR engine measures that the native engine cannot: CPU load (cycles not asleep), each
 * interrupt vector's entries, cycles and latency (pending to running), the functions that took
 * the most cycles (by the ELF's symbols), and the deepest the stack went. Kept in memory and
 * written as JSON into a file the simulator reads at the run's end (sear run puts it in its output
 * folder as ROBOT.MCU.avr.json). */
#ifndef SEAR_ENGINES_AVR_PROFILE_H
#define SEAR_ENGINES_AVR_PROFILE_H

#include <stdint.h>

struct elf_firmware_t;

/* `path` may be NULL: nothing is written. */
void avr_profile_init(const char *path, const struct elf_firmware_t *firmware);
/* The instructions from byte address pc took `cycles`: one, or a local run (local_runs.h) that
 * stays within the symbol pc is in. */
static inline void avr_profile_count(uint32_t pc, uint64_t cycles);
/* The flash words [*lo, *hi) whose cycles the report gives to the same symbol as `word`'s: a
 * function's, for one that a run (local_runs.h) may stay within. */
void avr_profile_symbol_words(uint32_t word, uint32_t *lo, uint32_t *hi);
/* The chip slept this many cycles. */
void avr_profile_sleep(uint64_t cycles);
/* The I flag changed: `on` is its new value, `pc` where the chip goes on from (after a CLI, the
 * next instruction; on an interrupt's entry, its vector), `cycle` the cycle it took effect. */
void avr_profile_interrupts_flag(int on, uint32_t pc, uint64_t cycle);
/* The cycles so far that the chip was not asleep. */
uint64_t avr_profile_busy_cycles(void);
/* Rewrites the report (cheap enough to call every few quanta; the simulator kills the engine
 * without warning, so the file must be current at any quantum's end). */
void avr_profile_write(void);

/* Per word of the ATmega2560's 256 KiB of flash, at a fixed address: counted for every instruction,
 * so no pointer or bound is loaded for it. A pc past the flash wraps, as the chip's does. */
#define AVR_PROFILE_WORDS 0x20000u
extern uint64_t avr_profile_pc_cycles[AVR_PROFILE_WORDS];

/* The flash word of byte address pc, the index of this and local_runs.h's per-word tables. */
static inline uint32_t avr_profile_word(uint32_t pc) { return (pc >> 1) & (AVR_PROFILE_WORDS - 1); }

static inline void avr_profile_count(uint32_t pc, uint64_t cycles) {
  avr_profile_pc_cycles[avr_profile_word(pc)] += cycles;
}

#endif
