/* USART0..3 at 8N1 with interrupt-driven 64-byte transmit and receive rings, and the per-port
 * receive handlers of irq_attach_uart_rx (they replace the receive ring, so they live here). */
#include <hal/irq.h>
#include <hal/uart.h>

#include <avr/interrupt.h>
#include <avr/io.h>
#include <stddef.h>
#include <util/atomic.h>

/* The four USARTs share one register layout from UCSRnA on (UCSRnA, UCSRnB, UCSRnC, reserved,
 * UBRRn, UDRn) and one set of bit positions, so USART0's bit names serve all of them. */
typedef struct {
    uint8_t ucsra, ucsrb, ucsrc, reserved;
    uint16_t ubrr;
    uint8_t udr;
} usart_regs;

/* Free-running 8-bit indices: count = head - tail wraps correctly since 256 is a multiple of
 * the ring size, and all 64 slots are usable (no empty slot to tell full from empty). */
#define RING_MASK (HAL_UART_BUFFER - 1u)

typedef struct {
    uint8_t rx[HAL_UART_BUFFER];
    uint8_t tx[HAL_UART_BUFFER];
    volatile uint8_t rx_head, rx_tail, tx_head, tx_tail;
    volatile uint8_t written; /* TXC only means something once a byte has been sent */
    volatile irq_byte_handler rx_handler;
} uart_state;

static uart_state uarts[HAL_UART_COUNT];

static volatile usart_regs *usart(uint8_t port)
{
    switch (port) {
    case 0: return (volatile usart_regs *)&UCSR0A;
    case 1: return (volatile usart_regs *)&UCSR1A;
    case 2: return (volatile usart_regs *)&UCSR2A;
    default: return (volatile usart_regs *)&UCSR3A;
    }
}

/* TXC is cleared by writing it one; FE, DOR and UPE must be written zero, U2X and MPCM kept. */
static void clear_tx_complete(volatile usart_regs *u)
{
    u->ucsra = (uint8_t)((u->ucsra & (_BV(U2X0) | _BV(MPCM0))) | _BV(TXC0));
}

static void on_receive(uint8_t port)
{
    volatile usart_regs *u = usart(port);
    uart_state *s = &uarts[port];
    uint8_t byte = u->udr;
    irq_byte_handler handler = s->rx_handler;
    if (handler) {
        handler(byte);
        return;
    }
    uint8_t head = s->rx_head;
    if ((uint8_t)(head - s->rx_tail) < HAL_UART_BUFFER) {
        s->rx[head & RING_MASK] = byte;
        s->rx_head = (uint8_t)(head + 1u);
    }
}

static void on_data_register_empty(uint8_t port)
{
    volatile usart_regs *u = usart(port);
    uart_state *s = &uarts[port];
    uint8_t tail = s->tx_tail;
    if (tail != s->tx_head) {
        clear_tx_complete(u);
        u->udr = s->tx[tail & RING_MASK];
        s->tx_tail = ++tail;
    }
    if (tail == s->tx_head)
        u->ucsrb &= (uint8_t)~_BV(UDRIE0);
}

ISR(USART0_RX_vect) { on_receive(0); }
ISR(USART1_RX_vect) { on_receive(1); }
ISR(USART2_RX_vect) { on_receive(2); }
ISR(USART3_RX_vect) { on_receive(3); }
ISR(USART0_UDRE_vect) { on_data_register_empty(0); }
ISR(USART1_UDRE_vect) { on_data_register_empty(1); }
ISR(USART2_UDRE_vect) { on_data_register_empty(2); }
ISR(USART3_UDRE_vect) { on_data_register_empty(3); }

void uart_begin(uint8_t port, uint32_t baud)
{
    if (port >= HAL_UART_COUNT || baud == 0)
        return;
    /* Datasheet, double speed: UBRR = f_osc / (8 * baud) - 1, rounded to the nearest; below
     * about 490 baud that exceeds UBRR's 12 bits and normal speed (16 * baud) takes over. */
    uint8_t double_speed = _BV(U2X0);
    uint32_t ubrr = (F_CPU / 8u + baud / 2u) / baud - 1u;
    if (ubrr > 4095u) {
        double_speed = 0;
        ubrr = (F_CPU / 16u + baud / 2u) / baud - 1u;
        if (ubrr > 4095u)
            ubrr = 4095u;
    }
    volatile usart_regs *u = usart(port);
    uart_state *s = &uarts[port];
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE) {
        u->ucsrb = 0;
        s->rx_head = s->rx_tail = s->tx_head = s->tx_tail = 0;
        s->written = 0;
        u->ucsra = double_speed;
        u->ubrr = (uint16_t)ubrr;
        u->ucsrc = _BV(UCSZ01) | _BV(UCSZ00); /* asynchronous, 8 data bits, no parity, 1 stop */
        u->ucsrb = _BV(RXEN0) | _BV(TXEN0) | _BV(RXCIE0);
    }
}

uint8_t uart_available(uint8_t port)
{
    if (port >= HAL_UART_COUNT)
        return 0;
    uart_state *s = &uarts[port];
    return (uint8_t)(s->rx_head - s->rx_tail);
}

int16_t uart_read(uint8_t port)
{
    if (port >= HAL_UART_COUNT)
        return -1;
    uart_state *s = &uarts[port];
    uint8_t tail = s->rx_tail;
    if (tail == s->rx_head)
        return -1;
    uint8_t byte = s->rx[tail & RING_MASK];
    s->rx_tail = (uint8_t)(tail + 1u);
    return byte;
}

static uint8_t interrupts_enabled(void)
{
    return (SREG & _BV(SREG_I)) != 0;
}

/* With interrupts off (inside a handler) the transmit interrupt cannot run, so whoever waits
 * for room moves the bytes out itself, or it would wait forever. */
static void drain_by_polling(uint8_t port)
{
    volatile usart_regs *u = usart(port);
    if (!interrupts_enabled() && (u->ucsrb & _BV(UDRIE0)) && (u->ucsra & _BV(UDRE0)))
        on_data_register_empty(port);
}

void uart_write(uint8_t port, uint8_t byte)
{
    if (port >= HAL_UART_COUNT)
        return;
    volatile usart_regs *u = usart(port);
    uart_state *s = &uarts[port];
    if (!(u->ucsrb & _BV(TXEN0)))
        return; /* not begun: nothing would ever empty the ring */
    for (;;) {
        /* Check and insert as one step: a handler may write to the same port meanwhile. */
        ATOMIC_BLOCK(ATOMIC_RESTORESTATE) {
            s->written = 1;
            uint8_t head = s->tx_head;
            if (head == s->tx_tail && (u->ucsra & _BV(UDRE0))) {
                /* Idle transmitter: straight into UDRn, no interrupt needed. */
                clear_tx_complete(u);
                u->udr = byte;
                return;
            }
            if ((uint8_t)(head - s->tx_tail) < HAL_UART_BUFFER) {
                s->tx[head & RING_MASK] = byte;
                s->tx_head = (uint8_t)(head + 1u);
                u->ucsrb |= _BV(UDRIE0);
                return;
            }
        }
        drain_by_polling(port);
    }
}

void uart_print(uint8_t port, const char *text)
{
    if (text == NULL)
        return;
    while (*text)
        uart_write(port, (uint8_t)*text++);
}

void uart_flush(uint8_t port)
{
    if (port >= HAL_UART_COUNT || !uarts[port].written)
        return;
    volatile usart_regs *u = usart(port);
    /* TXC sets once the shift register is empty with nothing in UDRn; every write clears it,
     * so it can only be set here after the last byte has left the pin. */
    while ((u->ucsrb & _BV(UDRIE0)) || !(u->ucsra & _BV(TXC0)))
        drain_by_polling(port);
}

void irq_attach_uart_rx(uint8_t port, irq_byte_handler handler)
{
    if (port >= HAL_UART_COUNT)
        return;
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE) {
        uarts[port].rx_handler = handler;
    }
}

/* The ring's free places; the data register's byte has already left the ring. */
uint8_t uart_tx_space(uint8_t port)
{
    if (port >= HAL_UART_COUNT)
        return 0;
    uart_state *s = &uarts[port];
    return (uint8_t)(HAL_UART_BUFFER - (uint8_t)(s->tx_head - s->tx_tail));
}
