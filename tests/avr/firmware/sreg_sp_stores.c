/* Register-level test firmware: interrupts turned off by a store to SREG (STS, not CLI) for ten
 * NOPs, and the stack pointer moved 40 bytes down by stores to SPH:SPL (OUT), then 2 more by two
 * PUSHes, and back, amid instructions that neither branch nor touch the I flag otherwise. The
 * first pass stores I on and moves the stack by the PUSHes only; from the second on, when the AVR
 * engine knows these instructions and runs them many to a call into simavr, the stores take
 * effect, and what it reports must still be what the chip did, cycle for cycle. */
#include <avr/interrupt.h>
#include <stdint.h>

static volatile uint8_t sreg_value = 0x80, depth = 0;

int main(void) {
  sei();
  for (;;) {
    const uint8_t s = sreg_value, d = depth;
    __asm__ volatile(
        "sts 0x5f, %0\n\t" /* SREG in the data space */
        "nop\n\tnop\n\tnop\n\tnop\n\tnop\n\tnop\n\tnop\n\tnop\n\tnop\n\tnop\n\t"
        "sei\n\t"
        "in r24, __SP_L__\n\t"
        "in r25, __SP_H__\n\t"
        "sub r24, %1\n\t"
        "sbc r25, __zero_reg__\n\t"
        "out __SP_H__, r25\n\t" /* no interrupt is enabled that could use the half-moved SP */
        "out __SP_L__, r24\n\t"
        "push r24\n\t"
        "push r25\n\t"
        "pop r25\n\t"
        "pop r24\n\t"
        "add r24, %1\n\t"
        "adc r25, __zero_reg__\n\t"
        "out __SP_H__, r25\n\t"
        "out __SP_L__, r24\n\t" ::"r"(s),
        "r"(d)
        : "r24", "r25", "memory");
    sreg_value = 0;
    depth = 40;
  }
}
