/* The global interrupt switch, kept apart from the pin and timer interrupts so that using it
 * links none of their handlers and tables. */
#include <hal/irq.h>

#include <avr/interrupt.h>

void irq_disable(void)
{
    cli();
}

void irq_enable(void)
{
    sei();
}
