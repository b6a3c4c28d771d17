/* What each in-process device model gives the firmware, told to the simulator through the link's
 * readings[] (lockstep_link.h, struct sear_link_reading) so that it can set them against the truth. */
#ifndef SEAR_HAL_RUNTIME_READINGS_H
#define SEAR_HAL_RUNTIME_READINGS_H

#include <stdint.h>

/* After any operation on input i at t_ns: its output may have changed. Cheap: only noted. */
void mcu_readings_touch(uint32_t input, int64_t t_ns);
/* Before the turn goes to the simulator, which reads readings[] only then: each touched input's
 * output, as at its last operation, published if it changed. An MPU-6000 burst read touches it
 * 15 times; its registers are decoded once a quantum. */
void mcu_readings_publish(void);

#endif
