/* Serial ports 0..3 (8 data bits, no parity, 1 stop bit). Port 0 is the console. Writes are
 * buffered (64 bytes) and block only while the buffer is full; each byte takes 10 bit times on
 * the wire. Received bytes wait in a 64-byte buffer; later ones are lost when it is full. */
#ifndef SEAR_HAL_UART_H
#define SEAR_HAL_UART_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define HAL_UART_COUNT 4
#define HAL_UART_BUFFER 64

void uart_begin(uint8_t port, uint32_t baud);
uint8_t uart_available(uint8_t port); /* bytes waiting to be read */
int16_t uart_read(uint8_t port);      /* the next byte, or -1 when none is waiting */
void uart_write(uint8_t port, uint8_t byte);
void uart_print(uint8_t port, const char *text);
void uart_flush(uint8_t port);        /* waits until every written byte has left the wire */
/* How many bytes uart_write() takes now without waiting: the 64-byte buffer's free places, after
 * the byte being shifted out and the one in the data register (0..HAL_UART_BUFFER). */
uint8_t uart_tx_space(uint8_t port);

#ifdef __cplusplus
}
#endif
#endif
