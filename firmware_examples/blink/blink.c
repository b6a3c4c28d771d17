/* The smallest SEAR firmware: the LED on pin 13 blinks at 1 Hz, and once a second the console
 * (UART 0, 115200 baud) reports the uptime and the reading of ADC channel 0. */
#include <hal/hal.h>

#include <inttypes.h>
#include <stdio.h>

#define LED_PIN 13
#define CONSOLE 0

int main(void)
{
    hal_init();
    pin_mode(LED_PIN, OUTPUT);
    uart_begin(CONSOLE, 115200);

    char line[48];
    uint8_t half_seconds = 0;
    for (;;) {
        delay_ms(500);
        digital_toggle(LED_PIN);
        if (++half_seconds < 2)
            continue;
        half_seconds = 0;
        /* Rounded: millis() moves in 1.024 ms timer steps, so after 1000 ms of delays it may
         * still read 999. int is 16 bits on the AVR, hence the explicit widths. */
        uint32_t uptime_s = (millis() + 500u) / 1000u;
        uint16_t a0 = adc_read(0);
        snprintf(line, sizeof line, "uptime %" PRIu32 " s, adc0 %" PRIu16 "\n", uptime_s, a0);
        uart_print(CONSOLE, line);
    }
}
