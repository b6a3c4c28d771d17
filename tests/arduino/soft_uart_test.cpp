// The HAL's soft UART (hal/soft_uart.h) from C firmware: a write holds interrupts off from the
// start bit's edge to the stop bit's, so another interrupt's latency grows to that, as on the chip.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <string>

#include "firmware_run.hpp"

using namespace sear::test;

namespace {

// A timer interrupt every 1013 us notes how late it runs (micros() in the handler against its
// due time), first for 300 ms with the main loop idle, then for 500 ms while the main loop sends
// bytes back to back on a soft UART at 9600 baud; it prints the worst of each.
const char* const kLatencyFirmware = R"(#include <hal/hal.h>
#include <stdio.h>
#define PERIOD_US 1013u
static volatile uint32_t due_us, worst_us;
static void tick(void) {
  const uint32_t late = micros() - due_us;
  if (late > worst_us) worst_us = late;
  due_us += PERIOD_US;
}
static uint32_t take_worst(void) {
  irq_disable();
  const uint32_t w = worst_us;
  worst_us = 0;
  irq_enable();
  return w;
}
int main(void) {
  hal_init();
  uart_begin(0, 115200);
  const uint8_t line = soft_uart_begin(10, 11, 9600, 0);
  due_us = micros() + PERIOD_US;
  irq_timer_start(PERIOD_US, tick);
  while (millis() < 300) {}
  const uint32_t quiet = take_worst();
  while (millis() < 800) soft_uart_write(line, 0x55);
  const uint32_t busy = take_worst();
  char text[64];
  snprintf(text, sizeof text, "quiet %lu busy %lu\n", (unsigned long)quiet, (unsigned long)busy);
  uart_print(0, text);
  for (;;) delay_ms(10);
}
)";

// Idle, a tick runs at the main loop's next HAL call: within one call's cost (50 cycles at 16 MHz,
// 3.125 us) plus micros()' truncation to whole us and the due time's (taken one call before the
// timer started): under 8 us. While a byte goes out, a tick due just after the start bit's edge
// waits until the stop bit's edge, 9 bit times = 9 / 9600 s = 937.5 us later (the library lets the
// stop bit's time pass with interrupts on). Ticks every 1013 us against bytes every 1041.7 us plus
// the loop's two calls (6.25 us) meet every phase within one step of (1047.9 - 1013) us = 35 us,
// so the worst seen lies within 35 us below 937.5 us, and above it by no more than the idle bound.
TEST(SoftUartLatency, AWriteHoldsAnotherInterruptOffForNineBitTimes) {
  TempDir dir;
  std::ofstream(dir.path() / "main.c") << kLatencyFirmware;
  const SearRun run = run_sear(
      dir, rover_project("    <mcu name=\"main\">\n      <firmware sources=\"main.c\"/>\n    </mcu>\n", "", 0.9));
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  unsigned long quiet = 0, busy = 0;
  const std::string console = run.file("rover.main.console.log");
  ASSERT_EQ(std::sscanf(console.c_str(), "%*s quiet %lu busy %lu", &quiet, &busy), 2) << console;
  EXPECT_LT(quiet, 8u);
  const double nine_bits_us = 9 / 9600.0 * 1e6;
  EXPECT_GE(static_cast<double>(busy), nine_bits_us - 35) << console;
  EXPECT_LE(static_cast<double>(busy), nine_bits_us + 8) << console;
}

}  // namespace
