/* Memory as a chip has it at every reset: the same in every run. A firmware that reads stack it
 * never wrote sees whatever ran there before, and on a host that includes per-process random words
 * (the stack protector's canary, copied into every protected frame, comes from the kernel's
 * AT_RANDOM bytes) and host times (the lockstep hand-off's clock readings and spin counts). Before
 * anything else of the process runs (.preinit_array, ahead of every constructor), the canary is
 * set to a fixed value and the stack below is painted; after each hand-off its dead frames are
 * painted again; and the idle-loop check's signals run on a stack of their own (idle.c). So such a
 * bug reproduces at every run as it would at every reset of the chip. */
#include "startup_memory.h"

#include <stdint.h>
#include <string.h>

/* A fixed canary with a zero low byte, as glibc makes its random one, so that a string copy
 * running over a buffer still cannot reproduce it. */
#define SEAR_STACK_CANARY 0x5EA75EA75EA75E00ull
/* The stack the firmware will use, painted: far more than an ATmega2560 has RAM (8 KiB). */
#define SEAR_STACK_PAINT_BYTES (256u * 1024u)
#define SEAR_STACK_PAINT 0xA5
/* Deeper than the hand-off's frames and the C library's clock and futex calls under them. */
#define SEAR_HANDOFF_PAINT_BYTES 4096u

/* Writes the canary where this ABI keeps it (the thread control block's stack_guard). On other
 * hosts the canary stays the kernel's, and only the paint applies. */
__attribute__((no_stack_protector)) static void fix_canary(void) {
#if defined(__x86_64__)
  __asm__ volatile("movq %0, %%fs:0x28" : : "r"((uint64_t)SEAR_STACK_CANARY) : "memory");
#elif defined(__i386__)
  __asm__ volatile("movl %0, %%gs:0x14" : : "r"((uint32_t)SEAR_STACK_CANARY) : "memory");
#endif
}

/* The paint goes below this function's frame, where main() and everything it calls will live:
 * a buffer of the stack's own, filled and then left, with an asm barrier so that the compiler
 * keeps stores nobody reads. It runs before a sanitizer runtime has set up its shadow memory, so
 * it must not be instrumented. */
__attribute__((no_stack_protector, noinline, no_sanitize("address", "undefined"))) static void paint_stack(void) {
  unsigned char below[SEAR_STACK_PAINT_BYTES];
  memset(below, SEAR_STACK_PAINT, sizeof below);
  __asm__ volatile("" : : "r"(below) : "memory");
}

/* Called where the hand-off was called from, so that its buffer lies over the frames the hand-off
 * just left. */
__attribute__((noinline, no_sanitize("address", "undefined"))) void mcu_paint_after_wait(void) {
  unsigned char below[SEAR_HANDOFF_PAINT_BYTES];
  memset(below, SEAR_STACK_PAINT, sizeof below);
  __asm__ volatile("" : : "r"(below) : "memory");
}

__attribute__((no_stack_protector)) static void reset_memory(void) {
  fix_canary();
  paint_stack();
}

__attribute__((section(".preinit_array"), used)) static void (*const sear_reset_memory)(void) = reset_memory;
