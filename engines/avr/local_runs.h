/* Local runs: stretches of instructions within one function, branches and skips included, which
 * the engine hands simavr in one call (its core's own loop, bounded by run_cycle_count) instead of
 * one call per instruction, with every observation the one-by-one loop reports still exact. */
#ifndef SEAR_ENGINES_AVR_LOCAL_RUNS_H
#define SEAR_ENGINES_AVR_LOCAL_RUNS_H

#include <stdint.h>

#include "profile.h"

/* Per flash word, the cycles simavr may be given for a run from the instruction beginning there:
 * no path from it reaches, within fewer instructions, one the loop must look at before it runs
 * (a jump to itself, SLEEP, WDR, BREAK, an encoding it does not know), and any path that runs
 * one that changes the I flag or leaves the function (a call, a return, CLI, a branch out of its
 * symbol) ends the run there. Every instruction takes a cycle at least, so a run of that many
 * cycles runs no more instructions than that. 0: the instruction runs on its own. */
extern uint16_t avr_run_budget[AVR_PROFILE_WORDS];

/* Classifies the image's flash, works out each word's budget, and hooks the writes that end a run
 * after their instruction (to SREG, and to SPL or SPH taking the stack pointer to a new low), so
 * that the I flag and the stack's low mark are seen as between single instructions. Returns 0,
 * and leaves every budget 0, when runs cannot be trusted: an image with SPM (the flash could
 * change under the table), SEAR_AVR_SINGLE_STEP set (the reference runs are tested against), or
 * those registers already hooked by someone else. */
int avr_local_runs_init(uint32_t code_end);

#endif
