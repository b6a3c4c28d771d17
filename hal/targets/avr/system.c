/* hal_init: the clock, timers, ADC and interrupts in the state the rest of the AVR HAL expects,
 * the same state the Arduino core's init() leaves a Mega in. */
#include <hal/system.h>

#include "timers.h"

#include <avr/interrupt.h>
#include <avr/io.h>

void hal_init(void)
{
    cli();
    hal_avr_time_start();
    hal_avr_timers_init();

    /* 16 MHz / 128 = 125 kHz, inside the 50..200 kHz the datasheet asks for 10-bit accuracy.
     * ADMUX (the reference) is left alone until the first adc_read: selecting AVCC now would
     * short it to a voltage wired to AREF before the firmware could choose ADC_REF_EXTERNAL. */
    ADCSRA = _BV(ADEN) | _BV(ADPS2) | _BV(ADPS1) | _BV(ADPS0);

    /* A bootloader may leave USART0 enabled; pins 0 and 1 are plain I/O until uart_begin. */
    UCSR0B = 0;

    sei();
}

/* Nothing to report to on the bench: the chip stops with interrupts off, as a sketch's halt does. */
void hal_refuse(const char *message)
{
    (void)message;
    cli();
    for (;;) {
    }
}
