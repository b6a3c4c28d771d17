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

/* The chip stops with interrupts off, as a sketch's halt does; the reason goes out on UART 0 first
 * when the firmware began it (the console a bench reads), byte by byte with interrupts off, after
 * whatever its ring still held is dropped. */
void hal_refuse(const char *message)
{
    cli();
    if (UCSR0B & _BV(TXEN0)) {
        UCSR0B &= (uint8_t)~_BV(UDRIE0);
        for (const char *c = message; *c; c++) {
            while (!(UCSR0A & _BV(UDRE0))) {
            }
            UDR0 = (uint8_t)*c;
        }
        while (!(UCSR0A & _BV(UDRE0))) {
        }
        UDR0 = '\n';
    }
    for (;;) {
    }
}
