/* GPS waypoint follower for the rover: a u-blox NEO-6M on UART3 (NMEA 0183 at 9600 baud, its
 * default) read through ../lib/nmea_reader; an HMC5883L compass on I2C for the heading; the rover
 * drives through a list of waypoints (latitude, longitude) and stops at the last.
 * Plain 8-bit C: int is 16 bits on the ATmega2560, so every wider value says so. */
#include <hal/hal.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "../lib/hmc5883l_i2c.h"
#include "../lib/motor_shield.h"
#include "../lib/nmea_reader.h"

#define PI_F 3.14159265f
#define CONSOLE 0
#define GPS 3 /* TX3 pin 14, RX3 pin 15 */

/* Magnetic declination where the rover drives, east positive: true = magnetic + declination.
 * It must match the project's <magnetic declination_deg>. */
#define DECLINATION_DEG 1.5f

/* The course: a 5 m square from the start (the project's gps_origin, 52.2053 N, 0.1218 E), in
 * 1e-5 arc minutes. 5 m north is 5 / 1853.2 m per minute = 270 units; 5 m east is 440 units at
 * cos(52.2053 deg) = 0.6127. */
static const struct fix_point waypoints[] = {
    {313231800L, 731240L}, /* 5 m east of the start */
    {313232070L, 731240L}, /* then 5 m north */
    {313232070L, 730800L}, /* then 5 m west */
    {313231800L, 730800L}, /* back to the start */
};
#define WAYPOINTS (sizeof waypoints / sizeof waypoints[0])
#define ARRIVED_M 1.0f /* a NEO-6M's fix wanders by about 2.5 m CEP: closer is luck */

#define CRUISE 150
#define SPIN 110
#define K_STEER 1.0f /* steer per radian of heading error */
#define SPIN_RAD 1.0f /* turn on the spot beyond this heading error */

static int16_t deg_of(float rad) { return (int16_t)lroundf(rad * 180.0f / PI_F); }

int main(void) {
  hal_init();
  uart_begin(CONSOLE, 115200);
  uart_begin(GPS, 9600);
  i2c_begin(400000);
  motors_begin();
  motors_drive(0, 0);
  uart_print(CONSOLE, "gps_waypoints: ready\r\n");
  while (!compass_begin()) {
    uart_print(CONSOLE, "compass: no HMC5883L at 0x1E, trying again\r\n");
    delay_ms(1000);
  }

  static struct nmea parser; /* static: 90 bytes better counted in .bss than found on the stack */
  struct gps_state gps;
  memset(&gps, 0, sizeof gps);
  uint8_t target = 0;
  uint32_t next_compass = millis(), next_report = millis();
  float heading = -1, distance = 0, bearing = 0, steer = 0;
  char line[96];
  for (;;) {
    int16_t byte;
    while ((byte = uart_read(GPS)) >= 0) nmea_feed(&parser, &gps, (uint8_t)byte);

    const uint32_t now = millis();
    if ((int32_t)(now - next_compass) >= 0) {
      next_compass += 67; /* the HMC5883L's 15 Hz */
      heading = compass_heading(DECLINATION_DEG);
      const uint8_t fresh = gps.valid && now - gps.at_ms < 2000u;
      if (target >= WAYPOINTS || !fresh || heading < 0) {
        motors_drive(0, 0);
      } else {
        float east, north;
        nmea_offset_m(&gps.at, &waypoints[target], &east, &north);
        distance = sqrtf(east * east + north * north);
        bearing = atan2f(east, north); /* clockwise from north */
        if (bearing < 0) bearing += 2 * PI_F;
        if (distance < ARRIVED_M) {
          snprintf(line, sizeof line, "waypoint %u reached\r\n", target + 1u);
          uart_print(CONSOLE, line);
          if (++target == WAYPOINTS) uart_print(CONSOLE, "course done\r\n");
        } else {
          float error = bearing - heading; /* positive: the waypoint is to the right */
          while (error > PI_F) error -= 2 * PI_F;
          while (error < -PI_F) error += 2 * PI_F;
          if (error > SPIN_RAD) {
            steer = -1;
            motors_drive(SPIN, -SPIN);
          } else if (error < -SPIN_RAD) {
            steer = 1;
            motors_drive(-SPIN, SPIN);
          } else {
            steer = -K_STEER * error; /* positive steer turns left */
            motors_drive((int16_t)((float)CRUISE * (1.0f - steer)), (int16_t)((float)CRUISE * (1.0f + steer)));
          }
        }
      }
    }

    if ((int32_t)(now - next_report) >= 0) {
      next_report += 1000;
      if (!gps.valid) {
        snprintf(line, sizeof line, "no fix (%u sats), heading %d deg, %u bad checksums\r\n", gps.sats,
                 heading < 0 ? -1 : deg_of(heading), parser.bad_checksums);
      } else {
        const int16_t s = (int16_t)lroundf(steer * 100.0f);
        const uint16_t s_abs = (uint16_t)(s < 0 ? -s : s);
        snprintf(line, sizeof line,
                 "fix %u sats: waypoint %u/%u at %u.%u m, bearing %d, heading %d deg, steer %c%u.%02u\r\n",
                 gps.sats, target < WAYPOINTS ? target + 1u : (unsigned)WAYPOINTS, (unsigned)WAYPOINTS,
                 (unsigned)distance, (unsigned)(distance * 10.0f) % 10u, deg_of(bearing),
                 heading < 0 ? -1 : deg_of(heading), s < 0 ? '-' : '+', s_abs / 100u, s_abs % 100u);
      }
      uart_print(CONSOLE, line);
    }
    delay_ms(2);
  }
}
