/* The MCP2515 stand-alone CAN controller as its datasheet (Microchip DS20001801) names it: SPI
 * instructions, register addresses and bits, and the bit-timing derivation can.c programs. */
#ifndef SEAR_HAL_AVR_MCP2515_H
#define SEAR_HAL_AVR_MCP2515_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* SPI instructions (datasheet table 12-1). */
#define MCP_RESET 0xC0
#define MCP_READ 0x03
#define MCP_WRITE 0x02
#define MCP_READ_RX0 0x90 /* READ RX BUFFER from RXB0SIDH; CS rising clears RX0IF */
#define MCP_READ_RX1 0x94 /* READ RX BUFFER from RXB1SIDH; CS rising clears RX1IF */
#define MCP_LOAD_TX0 0x40 /* LOAD TX BUFFER at TXBnSIDH: 0x40, 0x42, 0x44 for n = 0, 1, 2 */
#define MCP_RTS(n) (uint8_t)(0x80u | (1u << (n))) /* REQUEST TO SEND: 0x81, 0x82, 0x84 */
#define MCP_READ_STATUS 0xA0
#define MCP_RX_STATUS 0xB0
#define MCP_BIT_MODIFY 0x05

/* READ STATUS answer: RX0IF, RX1IF, then TXREQ and TXnIF of each transmit buffer. */
#define MCP_STATUS_RX0IF 0x01
#define MCP_STATUS_RX1IF 0x02
#define MCP_STATUS_TXREQ(n) (uint8_t)(0x04u << (2u * (n)))

/* Acceptance filters n = 0..5 (four bytes each: SIDH, SIDL, EID8, EID0) and masks n = 0, 1. */
#define MCP_RXF_SIDH(n) (uint8_t)((n) < 3 ? 4u * (n) : 0x10u + 4u * ((n) - 3u))
#define MCP_RXM_SIDH(n) (uint8_t)(0x20u + 4u * (n))

#define MCP_CANSTAT 0x0E
#define MCP_CANCTRL 0x0F
#define MCP_TEC 0x1C
#define MCP_REC 0x1D
#define MCP_CNF3 0x28
#define MCP_CNF2 0x29
#define MCP_CNF1 0x2A
#define MCP_CANINTE 0x2B
#define MCP_CANINTF 0x2C
#define MCP_EFLG 0x2D
#define MCP_TXB_CTRL(n) (uint8_t)(0x30u + 0x10u * (n)) /* SIDH at +1 ... DLC at +5, data at +6 */
#define MCP_RXB0CTRL 0x60
#define MCP_RXB1CTRL 0x70

/* CANCTRL.REQOP and CANSTAT.OPMOD, bits 7..5. */
#define MCP_MODE_MASK 0xE0
#define MCP_MODE_NORMAL 0x00
#define MCP_MODE_CONFIG 0x80
#define MCP_CANCTRL_ABAT 0x10 /* abort every pending transmission */

/* CNF1: SJW in 7..6, BRP in 5..0. CNF2: BTLMODE 7, SAM 6, PHSEG1 in 5..3, PRSEG in 2..0.
 * CNF3: PHSEG2 in 2..0. Each segment field holds its length in time quanta minus one. */
#define MCP_CNF2_BTLMODE 0x80

/* TXBnCTRL. */
#define MCP_TXB_TXREQ 0x08
#define MCP_TXB_TXP_MASK 0x03
/* TXBnSIDL, RXBnSIDL, RXFnSIDL. */
#define MCP_SIDL_SRR 0x10 /* in RXBnSIDL: a standard remote frame */
#define MCP_SIDL_EXIDE 0x08
/* TXBnDLC, RXBnDLC. */
#define MCP_DLC_RTR 0x40
#define MCP_DLC_MASK 0x0F

/* RXBnCTRL: RXM in 6..5 (00 filters on, 11 every frame), BUKT (RXB0 rolls over into RXB1). */
#define MCP_RXM_MASK 0x60
#define MCP_RXM_ANY 0x60
#define MCP_RXM_FILTERED 0x00
#define MCP_RXB0_BUKT 0x04

/* CANINTE / CANINTF. */
#define MCP_INT_RX0 0x01
#define MCP_INT_RX1 0x02

/* EFLG. */
#define MCP_EFLG_RX1OVR 0x80
#define MCP_EFLG_RX0OVR 0x40
#define MCP_EFLG_TXBO 0x20
#define MCP_EFLG_TXEP 0x10
#define MCP_EFLG_RXEP 0x08

/* CNF1..3 that make bitrate from an osc_hz crystal exactly (datasheet section 5): 0, or -1
 * when no prescaler and 8..25 quanta give it. Exposed for the host test of both crystals. */
int8_t mcp2515_bit_timing(uint32_t osc_hz, uint32_t bitrate, uint8_t cnf[3]);

#ifdef __cplusplus
}
#endif
#endif
