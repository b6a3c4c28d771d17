/* Quadrature wheel encoders decoded on every edge of both channels (pin-change interrupts): a
 * count is one edge of either channel, +1 forward when A leads B. */
#ifndef FIRMWARE_QUADRATURE_H
#define FIRMWARE_QUADRATURE_H
#include <stdint.h>

struct encoder {
  volatile int32_t count;
  volatile uint16_t errors; /* both channels changed at once: an edge was missed */
  volatile uint8_t state;
  uint8_t pin_a, pin_b;
};

/* Pins to inputs, the current state taken, and `on_edge` attached to both channels' pin-change
 * interrupts: a handler of the caller's that calls encoder_edge() for this encoder. */
void encoder_begin(struct encoder *e, void (*on_edge)(void));
/* For the encoder's pin-change handler, on an edge of either channel. */
void encoder_edge(struct encoder *e);
/* The count, read with the interrupts held off. */
int32_t encoder_count(struct encoder *e);

#endif
