/* What the HAL's calls are built on, layer by layer: the MCU's state (mcu_state.h), the
 * firmware's end of the link (link_end.h), pin levels (pins.h), the devices in the firmware's process (devices.h) and the scheduler of its virtual
 * time (scheduler.h). Included by the HAL calls and the idle-loop check at the top; the layers
 * below include only what lies under them. */
#ifndef SEAR_HAL_RUNTIME_MCU_H
#define SEAR_HAL_RUNTIME_MCU_H

#include "devices.h"
#include "idle.h"
#include "link_end.h"
#include "mcu_state.h"
#include "pins.h"
#include "scheduler.h"

#endif
