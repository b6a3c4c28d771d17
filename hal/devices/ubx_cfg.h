/* The NEO-6M's UBX CFG class (GPS.G6-SW-10018, "UBX Class CFG"): what each set command changes,
 * what a u-blox 6 refuses with ACK-NAK, and the answers to polls. Internal to ublox_neo6m.c. */
#ifndef SEAR_DEVICES_UBX_CFG_H
#define SEAR_DEVICES_UBX_CFG_H

#include <stdint.h>

#include "ublox_neo6m.h"

#ifdef __cplusplus
extern "C" {
#endif

#define UBX_CLASS_ACK 0x05
#define UBX_CLASS_CFG 0x06
#define UBX_CLASS_MON 0x0A
#define UBX_NMEA_CLASS 0xF0

#define UBX_UART1 1 /* CFG-PRT portID of the module's only UART pins (u-blox 6 spec, "Port Numbers") */
#define UBX_PROTO_UBX 1u   /* CFG-PRT inProtoMask / outProtoMask bits */
#define UBX_PROTO_NMEA 2u
#define UBX_MODE_8N1 0x08D0u /* charLen 11 (8 bit), parity 100 (none), nStopBits 00 (1) */

/* 1 if the module's UART offers this rate (4800 ... 115200 of the NEO-6 datasheet). */
int ubx_cfg_baud_ok(uint32_t baud);
/* The defaults of CFG-NAV5 and CFG-SBAS. */
void ubx_cfg_defaults(struct ublox_neo6m *s);
/* Handles the CFG message held in s (class, id, payload, length) that ended at t_ns. Returns 1 to
 * acknowledge it, 0 to refuse it (ACK-NAK), -1 if it was answered already. */
int ubx_cfg(struct ublox_neo6m *s, int64_t t_ns);

/* Defined in ublox_neo6m.c: a UBX message sent in answer to a command that ended at t_ns, and
 * the ACK-ACK (ok) or ACK-NAK of the message being handled. */
void ublox_neo6m_reply(struct ublox_neo6m *s, int64_t t_ns, uint8_t cls, uint8_t id, const uint8_t *payload,
                       uint16_t len);
void ublox_neo6m_acknowledge(struct ublox_neo6m *s, int64_t t_ns, int ok);

#ifdef __cplusplus
}
#endif
#endif
