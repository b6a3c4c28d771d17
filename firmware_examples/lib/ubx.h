/* u-blox UBX binary messages to and from a GPS receiver on a UART, alongside its NMEA output:
 * frames sent with their Fletcher checksum, and the receiver's ACK-ACK / ACK-NAK picked out of
 * the bytes it sends. u-blox 6 Receiver Description, "UBX Protocol". */
#ifndef FIRMWARE_UBX_H
#define FIRMWARE_UBX_H
#include <stdint.h>

#define UBX_ACK_NONE 0
#define UBX_ACK_ACK 1
#define UBX_ACK_NAK 2

/* Sends B5 62, class, id, length, payload and the checksum on `port`. */
void ubx_send(uint8_t port, uint8_t cls, uint8_t id, const uint8_t *payload, uint16_t length);

/* Every byte from the receiver goes here too (NMEA bytes pass through unharmed). Remembers the
 * last acknowledgement seen: its kind and the class and id it answers. */
void ubx_feed(uint8_t byte);
/* UBX_ACK_ACK or UBX_ACK_NAK once the receiver has answered class/id since ubx_send(), else
 * UBX_ACK_NONE. */
uint8_t ubx_ack(uint8_t cls, uint8_t id);

#endif
