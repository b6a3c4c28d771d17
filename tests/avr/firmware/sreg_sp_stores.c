/* Register-level test firmware: interrupts turned off by a store to SREG (STS, not CLI) for ten
 * NOPs and on again by another (OUT, not SEI), and the stack pointer moved 40 bytes down by
 * stores to SPH:SPL (OUT), then 2 more by two PUSHes, and back, amid instructions that neither
 * branch nor touch the I flag otherwise: once, inside one of the runs of many instructions to a
 * call into simavr that the AVR engine makes, where what it reports must still be what the chip
 * did, cycle for cycle. Done once, so that a store the engine missed cannot be made up for by a
 * later pass that a cycle timer happened to cut at the store. */
#include <avr/interrupt.h>
#include <stdint.h>

int main(void) {
  sei();
  __asm__ volatile(
      "sts 0x5f, %0\n\t" /* SREG in the data space */
      "nop\n\tnop\n\tnop\n\tnop\n\tnop\n\tnop\n\tnop\n\tnop\n\tnop\n\tnop\n\t"
      "out __SREG__, %2\n\t" /* on again: simavr's core stops after it by itself */
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
      "out __SP_L__, r24\n\t" ::"r"((uint8_t)0),
      "r"((uint8_t)40), "r"((uint8_t)0x80)
      : "r24", "r25", "memory");
  for (;;) __asm__ volatile("nop");
}
