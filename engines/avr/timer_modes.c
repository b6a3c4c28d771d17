/* The timers' phase-correct PWM modes, which Debian's simavr 1.6 leaves undefined on the
 * ATmega2560 (see avr_timer_modes_define in engine.h). */
#include <string.h>

#include <avr_timer.h>
#include <sim_avr.h>
#include <sim_io.h>

#include "engine.h"

/* simavr 1.6 gives an undefined mode a TOP of 0, so a timer in one overflows and matches every
 * compare channel at each prescaled tick: at the HAL's and the Arduino core's default (8-bit
 * phase-correct PWM at clk/64) each of timers 1..5 and 2 raised four interrupt flags every 64
 * cycles, a flag the chip raises every 32640, and that churn took most of the engine's host
 * time. simavr counts single-slope only, so these modes are given its nearest: the mode's TOP
 * (a constant, ICRn or OCRnA) with counting 0..TOP. TCNTn and the compare flags stay within the
 * right range and TOVn comes every TOP + 1 counts, where the chip counts up and back down and
 * sets it every 2 TOP; the PWM outputs themselves are read from the registers (pins.c) and are
 * exact. Only modes simavr left empty are filled: a simavr that defines them keeps its own. */
static void define_16bit(avr_timer_t *t) {
  /* ATmega2560 datasheet, table 17-2: modes 1..3 phase correct 8/9/10-bit, 8 and 10 with TOP
   * = ICRn, 9 and 11 with TOP = OCRnA. */
  const avr_timer_wgm_t modes[16] = {
      [1] = AVR_TIMER_WGM_FCPWM8(), [2] = AVR_TIMER_WGM_FCPWM9(), [3] = AVR_TIMER_WGM_FCPWM10(),
      [8] = AVR_TIMER_WGM_ICPWM(),  [9] = AVR_TIMER_WGM_OCPWM(),  [10] = AVR_TIMER_WGM_ICPWM(),
      [11] = AVR_TIMER_WGM_OCPWM(),
  };
  for (int m = 0; m < 16; ++m)
    if (t->wgm_op[m].kind == avr_timer_wgm_none && modes[m].kind != avr_timer_wgm_none) t->wgm_op[m] = modes[m];
}

static void define_8bit(avr_timer_t *t) {
  /* Table 16-8 (timer0) and 20-8 (timer2): mode 1 phase correct to 0xFF, mode 5 to OCRnA. */
  const avr_timer_wgm_t modes[8] = {[1] = AVR_TIMER_WGM_FCPWM8(), [5] = AVR_TIMER_WGM_OCPWM()};
  for (int m = 0; m < 8; ++m)
    if (t->wgm_op[m].kind == avr_timer_wgm_none && modes[m].kind != avr_timer_wgm_none) t->wgm_op[m] = modes[m];
}

int avr_timer_modes_define(struct avr_t *avr) {
  int timers = 0;
  for (avr_io_t *io = avr->io_port; io; io = io->next) {
    if (!io->kind || strcmp(io->kind, "timer") != 0) continue;
    avr_timer_t *t = (avr_timer_t *)io;
    /* Timers 0 and 2 are the 8-bit ones; simavr names them by their digit. */
    if (t->name == '0' || t->name == '2') define_8bit(t);
    else define_16bit(t);
    timers++;
  }
  return timers;
}
