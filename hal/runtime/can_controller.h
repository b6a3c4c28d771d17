/* The CAN controller's side towards the scheduler: records from the bus join its queue when a
 * quantum begins and are applied once the firmware's clock reaches them. */
#ifndef SEAR_HAL_RUNTIME_CAN_CONTROLLER_H
#define SEAR_HAL_RUNTIME_CAN_CONTROLLER_H

#include "lockstep_link.h"

/* Queues a record the simulator sent for this quantum (they come in time order). */
void mcu_can_arrive(const struct sear_link_can *record);
/* Applies a record that fell due: a reception through the filters into the receive buffers, or
 * the outcome of a send. */
void mcu_can_apply(const struct sear_link_can *record);

#endif
