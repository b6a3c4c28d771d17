/* Reads the MPU-6000's latched data-ready interrupt as a driver does: when INT is high, it reads
 * INT_STATUS over SPI, which clears it (register map 4.16) and so drops INT. The chip takes the
 * falling edge's interrupt during the busy-wait on SPIF, so its handler has run by the time
 * spi_transfer returns; the probe counts the reads after which it had not. Prints, at 0.5 s:
 * "reads N late M falls F". */
#include <hal/hal.h>
#include <stdio.h>

#define MPU_CS 53
#define MPU_INT 63

static volatile uint32_t falls;

static void on_fall(void) { falls++; }

static void mpu_write(uint8_t reg, uint8_t value) {
  digital_write(MPU_CS, LOW);
  spi_transfer(reg);
  spi_transfer(value);
  digital_write(MPU_CS, HIGH);
}

int main(void) {
  hal_init();
  uart_begin(0, 115200);
  pin_mode(MPU_CS, OUTPUT);
  digital_write(MPU_CS, HIGH);
  pin_mode(MPU_INT, INPUT);
  spi_begin(3, 1000000);
  mpu_write(0x6B, 0x01); /* PWR_MGMT_1: awake, gyro PLL clock */
  mpu_write(0x1A, 0x03); /* CONFIG: DLPF 44 Hz, so a 1 kHz internal rate */
  mpu_write(0x19, 9);    /* SMPLRT_DIV: data ready at 100 Hz */
  mpu_write(0x37, 0x20); /* INT_PIN_CFG: LATCH_INT_EN, active high, cleared by reading INT_STATUS */
  mpu_write(0x38, 0x01); /* INT_ENABLE: DATA_RDY_EN */
  irq_attach_pin(MPU_INT, IRQ_FALLING, on_fall);
  uint32_t reads = 0, late = 0;
  while (millis() < 500) {
    if (!digital_read(MPU_INT)) continue;
    const uint32_t before = falls;
    digital_write(MPU_CS, LOW);
    spi_transfer(0x3A | 0x80);
    spi_transfer(0); /* INT_STATUS */
    if (falls == before) late++;
    digital_write(MPU_CS, HIGH);
    reads++;
  }
  char line[64];
  snprintf(line, sizeof line, "reads %lu late %lu falls %lu\n", (unsigned long)reads, (unsigned long)late,
           (unsigned long)falls);
  uart_print(0, line);
  for (;;) delay_ms(100);
}
