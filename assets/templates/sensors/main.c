/* @NAME@: a sensor demo that prints what each sensor tells the firmware, on the console (UART 0):
 *   a Sharp GP2D12 infrared ranger on ADC 0 (volts: the firmware turns them into centimetres),
 *   an HC-SR04 ultrasonic ranger (a pulse on pin 24 starts it; the echo on pin 10 lasts 58 us/cm),
 *   a u-blox NEO-6M GPS on UART 3 (NMEA sentences at 9600 baud; the GGA lines are printed),
 *   an InvenSense MPU-6000 IMU on SPI, chip select on pin 53 (registers: who am I, acceleration).
 * The same file builds for SEAR's simulator and for an ATmega2560: only <hal/hal.h> separates it
 * from the hardware. int is 16 bits on the AVR, so every wider value says so. */
#include <hal/hal.h>
#include <stdio.h>

#define IR_CHANNEL 0
#define SONAR_TRIG 24
#define SONAR_ECHO 10
#define GPS_UART 3
#define IMU_CS 53
#define REPORT_MS 500

/* Centimetres from a GP2D12 reading (10 bits, 5 V reference), the usual fit to the datasheet's
 * curve: cm = 6787 / (code - 3) - 4, good over 10..80 cm; 0 means nothing in range. */
static uint16_t ir_cm(void) {
  const uint16_t code = adc_read(IR_CHANNEL);
  if (code < 84) return 0;
  return (uint16_t)(6787u / (code - 3u) - 4u);
}

/* Centimetres from one HC-SR04 ping, timed by polling (a real loop, as on the bench); 0 when no
 * echo came back within 30 ms. */
static uint16_t sonar_cm(void) {
  digital_write(SONAR_TRIG, HIGH);
  delay_us(12); /* datasheet: at least 10 us */
  digital_write(SONAR_TRIG, LOW);
  const uint32_t start = micros();
  while (!digital_read(SONAR_ECHO))
    if (micros() - start > 30000ul) return 0;
  const uint32_t rise = micros();
  while (digital_read(SONAR_ECHO))
    if (micros() - rise > 30000ul) return 0;
  return (uint16_t)((micros() - rise) / 58u);
}

/* MPU-6000 registers over SPI: bit 7 of the address set for a read. */
static uint8_t imu_read(uint8_t reg) {
  digital_write(IMU_CS, LOW);
  spi_transfer((uint8_t)(reg | 0x80u));
  const uint8_t value = spi_transfer(0);
  digital_write(IMU_CS, HIGH);
  return value;
}

static void imu_write(uint8_t reg, uint8_t value) {
  digital_write(IMU_CS, LOW);
  spi_transfer(reg);
  spi_transfer(value);
  digital_write(IMU_CS, HIGH);
}

/* Acceleration along the IMU's z axis: +-2 g full scale, 16384 per g. */
static int16_t imu_az(void) {
  const uint8_t high = imu_read(0x3F), low = imu_read(0x40); /* ACCEL_ZOUT_H, _L */
  return (int16_t)(((uint16_t)high << 8) | low);
}

int main(void) {
  /* ---- setup: runs once ---- */
  hal_init();
  uart_begin(0, 115200); /* the console: sear's rover.main.console.log, the board's USB serial */
  uart_begin(GPS_UART, 9600);
  pin_mode(SONAR_TRIG, OUTPUT);
  digital_write(SONAR_TRIG, LOW);
  pin_mode(SONAR_ECHO, INPUT);
  pin_mode(IMU_CS, OUTPUT);
  digital_write(IMU_CS, HIGH);
  spi_begin(3, 1000000ul); /* mode 3, 1 MHz: the MPU-6000's limit for writing registers */
  imu_write(0x6B, 0x00);   /* PWR_MGMT_1: it wakes from reset asleep */
  imu_write(0x6A, 0x10);   /* USER_CTRL: SPI only */
  delay_ms(100);           /* the rangers' first measurements are ready */
  char line[100];
  snprintf(line, sizeof line, "@NAME@: ready, imu who_am_i 0x%02X\r\n", imu_read(0x75));
  uart_print(0, line);

  /* ---- loop: runs forever ---- */
  char nmea[84]; /* NMEA 0183: at most 82 characters a sentence */
  uint8_t nmea_length = 0;
  uint32_t next_report = millis();
  for (;;) {
    /* GPS: gather each sentence, print the GGA ones (the fix: time, position, satellites). */
    while (uart_available(GPS_UART)) {
      const char c = (char)uart_read(GPS_UART);
      if (c == '$') nmea_length = 0;
      if (c == '\r' || c == '\n') {
        nmea[nmea_length] = '\0';
        if (nmea_length > 6 && nmea[3] == 'G' && nmea[4] == 'G' && nmea[5] == 'A') {
          snprintf(line, sizeof line, "gps: %s\r\n", nmea);
          uart_print(0, line);
        }
        nmea_length = 0;
      } else if (nmea_length < sizeof nmea - 1) {
        nmea[nmea_length++] = c;
      }
    }

    if ((int32_t)(millis() - next_report) >= 0) {
      next_report += REPORT_MS;
      snprintf(line, sizeof line, "ir: %u cm\r\n", ir_cm());
      uart_print(0, line);
      snprintf(line, sizeof line, "sonar: %u cm\r\n", sonar_cm());
      uart_print(0, line);
      snprintf(line, sizeof line, "imu: az %d (16384 = 1 g)\r\n", imu_az());
      uart_print(0, line);
    }
    delay_ms(2);
  }
}
