/* Drives every in-process model the readings test wires, as a driver would: the MPU-6000 (chip
 * select 53) woken at +-4 g and +-500 deg/s, 44 Hz DLPF, 100 samples/s; the HMC5883L at 8-sample
 * averages, 15 Hz, +-1.3 Ga; both read every 5 ms. The IR ranger and the encoders need no help.
 * Built with SCRIBBLE_READING, it writes a NaN into the first input's reading after 100 ms, as a
 * stray pointer could: the simulator must stop it as corrupted. */
#include <hal/hal.h>
#include <stdlib.h>
#include <string.h>

#include "../../firmware_examples/lib/hmc5883l_i2c.h"
#include "../../firmware_examples/lib/mpu6000_spi.h"

#ifdef SCRIBBLE_READING
#include <math.h>
#include <stdio.h>

#include "find_link.h"
#endif

static const struct mpu_settings settings = {9, 0x03, 0x08, 0x08};

int main(void) {
  hal_init();
  uart_begin(0, 115200);
  mpu_select_pin(53);
  i2c_begin(400000);
  delay_ms(50);
  uart_print(0, mpu_begin(&settings, 0x00) ? "imu ok\n" : "imu failed\n");
  uart_print(0, compass_begin() ? "compass ok\n" : "compass failed\n");
#ifdef SCRIBBLE_READING
  delay_ms(50);
  struct sear_link *link = find_link();
  link->readings[0].value[0] = NAN;
  link->readings[0].count++;
#endif
  for (;;) {
    int16_t x, y, z;
    (void)mpu_read_sample();
    (void)compass_read(&x, &y, &z);
    delay_ms(5);
  }
}
