/* Straight runs: stretches of instructions that neither branch nor touch the I flag, which the
 * engine hands simavr in one call (its core's own loop, bounded by run_cycle_count) instead of
 * one call per instruction, with every observation the one-by-one loop makes still exact. */
#ifndef SEAR_ENGINES_AVR_STRAIGHT_RUNS_H
#define SEAR_ENGINES_AVR_STRAIGHT_RUNS_H

#include <stdint.h>

#include "profile.h"

/* Per flash word, what the instruction beginning there is. 0: one the engine runs on its own (a
 * jump, call, return, branch, skip, SREG bit, SLEEP, WDR, SPM...), since where it goes or
 * whether interrupts may then come is what the loop between instructions looks at. Else a
 * straight one: STRAIGHT_TWO_WORDS if it is LDS or STS, and its cycles in the low bits once it
 * has run on its own (STRAIGHT_UNSEEN until then), so that the cycles of a run are known
 * before it runs (a bound for simavr) and each instruction's are known after (the profile). */
enum { STRAIGHT_CYCLES = 0x0f, STRAIGHT_TWO_WORDS = 0x10, STRAIGHT_UNSEEN = 0x20 };
extern uint8_t avr_straight[AVR_PROFILE_WORDS];

/* Per flash word, the whole run from there to the next instruction that runs on its own, once
 * each of its instructions has been seen (cycles 0 until then), and how many times it ran whole
 * since its cycles last went into the profile (avr_straight_settle). */
struct straight_run {
  uint16_t cycles, bytes;
  uint32_t times;
};
extern struct straight_run avr_straight_runs[AVR_PROFILE_WORDS];

/* Classifies the image's flash and hooks the writes that end a run after their instruction (to
 * SREG, and to SPL or SPH taking the stack pointer to a new low), so that the I flag and the
 * stack's low mark are seen as between single instructions. Returns 0, and leaves every word 0,
 * when runs cannot be trusted: an image with SPM (the flash could change under the table),
 * SEAR_AVR_SINGLE_STEP set (the reference the runs are tested against), or those registers
 * already hooked by someone else. */
int avr_straight_init(uint32_t code_end);

/* Adds the cycles of the whole runs counted so far to the profile's per-word counts. */
void avr_straight_settle(void);

static inline uint32_t avr_straight_word(uint32_t pc) { return (pc >> 1) & (AVR_PROFILE_WORDS - 1); }

static inline uint32_t avr_straight_next(uint32_t pc, uint8_t kind) {
  return pc + ((kind & STRAIGHT_TWO_WORDS) ? 4u : 2u);
}

/* Walks the instructions known to be straight from pc until `room` cycles are reached: their
 * cycles, and in `*end` the pc after them. The whole run from pc, once known, is kept. */
uint64_t avr_straight_walk(uint32_t pc, uint64_t room, uint32_t code_end, uint32_t *end);

/* The run to hand simavr from pc, whose instruction is straight and known, within `room`
 * cycles: the whole run when it fits (`*whole` set), else as much of it as reaches `room`. */
static inline uint64_t avr_straight_plan(uint32_t pc, uint64_t room, uint32_t code_end, uint32_t *end, int *whole) {
  const struct straight_run *run = &avr_straight_runs[avr_straight_word(pc)];
  if (run->cycles && run->cycles <= room) {
    *end = pc + run->bytes;
    *whole = 1;
    return run->cycles;
  }
  *whole = 0;
  return avr_straight_walk(pc, room, code_end, end);
}

/* The instruction at pc ran on its own and took `cycles`: a straight one takes as many every
 * time (none of them depends on data for its timing), so it may now be part of a run. */
static inline void avr_straight_learn(uint32_t pc, uint64_t cycles) {
  uint8_t *kind = &avr_straight[avr_straight_word(pc)];
  if ((*kind & STRAIGHT_UNSEEN) && cycles >= 1 && cycles <= STRAIGHT_CYCLES)
    *kind = (uint8_t)((*kind & STRAIGHT_TWO_WORDS) | cycles);
}

/* A run from pc ran to `ran_to` `times` times (not past `end`, where it was planned to stop):
 * each instruction's cycles go to the profile. Returns the cycles of one time. */
uint64_t avr_straight_count(uint32_t pc, uint32_t ran_to, uint32_t end, uint64_t times);

#endif
