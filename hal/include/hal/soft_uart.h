/* Soft UARTs: 8N1 on two plain pins, as Arduino's SoftwareSerial makes them. Receive only on a
 * pin with a pin-change interrupt (10..15, 50..53, A8..A15) and only on one line at a time, the
 * listener, into a 64-byte ring (63 bytes wait at most; later ones are lost and flagged). A write
 * sends its byte at once, bit by bit, with interrupts held off from the start bit's edge to the
 * stop bit's (9 bit times), so any other interrupt may wait that long, and nothing is received
 * meanwhile. */
#ifndef SEAR_HAL_SOFT_UART_H
#define SEAR_HAL_SOFT_UART_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define HAL_SOFT_UART_COUNT 4   /* lines open at once */
#define HAL_SOFT_UART_BUFFER 64 /* the listener's receive ring */

/* Opens a line at baud (300..115200) with RX on rx_pin and TX on tx_pin (driven idle at once);
 * inverted: 1 for RS-232 polarity at logic levels (idle low, bits inverted). The line becomes
 * the listener. Returns its id, 0..HAL_SOFT_UART_COUNT-1. */
uint8_t soft_uart_begin(uint8_t rx_pin, uint8_t tx_pin, uint32_t baud, uint8_t inverted);
void soft_uart_end(uint8_t id);                /* closes it; its TX pin keeps its level */
uint8_t soft_uart_listen(uint8_t id);          /* makes it the listener (its ring emptied); 1 if it was not */
uint8_t soft_uart_stop_listening(uint8_t id);  /* 1 if it was the listener; then none is */
uint8_t soft_uart_is_listening(uint8_t id);
uint8_t soft_uart_available(uint8_t id);       /* bytes waiting; 0 unless it is the listener */
int16_t soft_uart_read(uint8_t id);            /* the next byte, or -1 */
int16_t soft_uart_peek(uint8_t id);            /* the next byte, left waiting, or -1 */
void soft_uart_write(uint8_t id, uint8_t byte); /* returns after the stop bit */
uint8_t soft_uart_overflow(uint8_t id);        /* 1 if a byte was lost to a full ring since the last call */

#ifdef __cplusplus
}
#endif
#endif
