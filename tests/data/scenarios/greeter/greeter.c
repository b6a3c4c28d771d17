/* The firmware of `sear test`'s own test suite: greets on its console (UART 0) a tenth of a second
 * after reset, then says "tick" once a second. */
#include <hal/hal.h>

#define CONSOLE 0

int main(void)
{
    hal_init();
    uart_begin(CONSOLE, 115200);
    delay_ms(100);
    uart_print(CONSOLE, "hello from the greeter\n");
    for (;;) {
        delay_ms(1000);
        uart_print(CONSOLE, "tick\n");
    }
}
