/* Passing the lockstep turn between two processes through a word in shared memory: spin briefly,
 * because a spinning hand-off costs well under a microsecond, then sleep on a futex, because a
 * peer that is busy for long must not cost a whole core. */
#ifndef SEAR_LOCKSTEP_HANDOFF_H
#define SEAR_LOCKSTEP_HANDOFF_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Sets *turn to `value` and wakes the peer if it sleeps (*peer_waiting set). */
void sear_handoff_give(uint32_t *turn, uint32_t value, uint32_t *peer_waiting);

/* Waits until *turn equals `value`: spins for spin_ns, then sleeps. Returns 1 once it does, or 0
 * when timeout_ns (< 0: none) passed first, so that the caller can check on its peer. */
int sear_handoff_wait(uint32_t *turn, uint32_t value, uint32_t *self_waiting, int64_t spin_ns,
                      int64_t timeout_ns);

/* How many PAUSEs a wait spins before it first yields, in this process: none where the process may
 * run on one CPU only (its peer cannot run until it yields), a few dozen otherwise. */
unsigned sear_handoff_spin_pauses(void);

#ifdef __cplusplus
}
#endif
#endif
