/* Register-level test firmware: where a local run of the AVR engine must end, reached by paths
 * of one-cycle instructions, so that a run one instruction too long shows in the report: a CLI
 * two NOPs after a return, then ten NOPs and an SEI; a tail jump out of one function into the
 * next, 1000 times; then a loop that calls nothing. */
#include <avr/interrupt.h>
#include <stdint.h>

/* Ten NOPs and a RET: 15 cycles a call (RET takes 5 on this 3-byte-PC part). */
__asm__(".global fifteen_cycles\n"
        ".type fifteen_cycles, @function\n"
        "fifteen_cycles:\n"
        "  nop\n  nop\n  nop\n  nop\n  nop\n  nop\n  nop\n  nop\n  nop\n  nop\n"
        "  ret\n"
        ".size fifteen_cycles, .-fifteen_cycles\n");

/* Two NOPs and a jump into fifteen_cycles, whose RET returns to the caller: 4 cycles a call. */
__asm__(".global tail_jump\n"
        ".type tail_jump, @function\n"
        "tail_jump:\n"
        "  nop\n  nop\n"
        "  rjmp fifteen_cycles\n"
        ".size tail_jump, .-tail_jump\n");

int main(void) {
  sei();
  /* Once, so that no later pass that a cycle timer happened to cut at the CLI can make up for a
   * run that went past it. (A run cannot go past the SEI: simavr's core stops after an
   * instruction that sets the I flag, whatever it was given.) */
  __asm__ volatile(
      "rcall tail_jump\n\t"
      "nop\n\tnop\n\t"
      "cli\n\t"
      "nop\n\tnop\n\tnop\n\tnop\n\tnop\n\tnop\n\tnop\n\tnop\n\tnop\n\tnop\n\t"
      "sei\n\t" ::
          : "memory");
  for (uint16_t call = 1; call < 1000; ++call) __asm__ volatile("rcall tail_jump" ::: "memory");
  for (;;) __asm__ volatile("nop");
}
