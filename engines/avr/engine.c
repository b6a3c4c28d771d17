/* sear-avr-engine: the AVR image that would be flashed, run instruction by instruction on
 * libsimavr's ATmega2560 as another firmware side of the lockstep link (DESIGN.md). The simulator
 * starts it in place of a native firmware: `sear-avr-engine --clock-hz HZ FIRMWARE.elf`, with the
 * link as for any firmware. Each quantum is an exact number of cycles; samples, received bytes
 * and device events are applied at the cycle they fall due, and what the chip does comes back as
 * the same events a native firmware makes. */
#define _GNU_SOURCE
#include "engine.h"

#include <inttypes.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <sim_avr.h>
#include <sim_elf.h>
#include <avr_extint.h>
#include <sim_core.h>
#include <sim_interrupts.h>

#include "devices.h"
#include "firmware_end.h"
#include "profile.h"
#include "readings.h"
#include "local_runs.h"

struct engine engine;

/* The longest stretch the chip runs without a look at its timer outputs: PWM duty and servo
 * pulses are read from registers (simavr 1.6 gives no PWM pin edges), so a change is stamped
 * at most this late; 1024 cycles are 64 us at 16 MHz. */
#define SLICE_CYCLES 1024u

static uint64_t slice_end_cycle;
static char last_error[160]; /* simavr's last complaint, for the crash report */

int64_t engine_ns_of_cycle(uint64_t cycle) {
  const uint64_t f = engine.clock_hz;
  return (int64_t)(cycle / f * 1000000000u + cycle % f * 1000000000u / f);
}

uint64_t engine_cycle_at_or_after(int64_t t_ns) {
  if (t_ns <= 0) return 0;
  const uint64_t t = (uint64_t)t_ns, f = engine.clock_hz;
  const uint64_t whole = t / 1000000000u, part = t % 1000000000u;
  return whole * f + (part * f + 999999999u) / 1000000000u;
}

int64_t engine_now_ns(void) {
  const int64_t t = engine_ns_of_cycle(engine.avr->cycle);
  if (t > engine.quantum_end_ns) return engine.quantum_end_ns;
  return t < engine.turn_start_ns ? engine.turn_start_ns : t;
}

static void hand_over(enum sear_request request) {
  avr_eeprom_save();
  sear_end_give(engine.link, request);
  sear_end_wait_for_turn(engine.link);
}

void engine_emit(enum sear_event_kind kind, uint8_t index, uint32_t value, int64_t time_ns) {
  struct sear_link *link = engine.link;
  if (sear_end_events_full(link)) {
    /* The clock goes with the events, as the native HAL's does: the simulator takes a full
     * queue at an unmoved clock for a loop that takes no time, and no event may lie past it. */
    link->clock_ns = engine_now_ns();
    hand_over(SEAR_REQUEST_DRAIN);
  }
  sear_end_push_event(link, kind, index, value, time_ns);
}

void engine_fatal(const char *format, ...) {
  struct sear_link *link = engine.link;
  /* A chip that fails within a turn has run to its failure: the events it made on the way carry
   * their cycles' times, so the clock goes there with them, as a native firmware's moves with each
   * call (never past the quantum's end, which the simulator holds it to). */
  if (engine.avr && engine.quantum_end_ns > link->clock_ns) {
    const int64_t now = engine_now_ns();
    if (now > link->clock_ns) link->clock_ns = now < engine.quantum_end_ns ? now : engine.quantum_end_ns;
  }
  va_list args;
  va_start(args, format);
  sear_end_set_fatal(link, format, args);
  va_end(args);
  if (engine.avr) avr_eeprom_save();
  fprintf(stderr, "sear-avr-engine: %s\n", link->fatal);
  sear_end_give(link, SEAR_REQUEST_FATAL);
  _exit(70);
}

/* simavr's messages go to the host log; its last error names what a crash was. */
static void logger(avr_t *avr, const int level, const char *format, va_list ap) {
  (void)avr;
  if (level > LOG_WARNING) return;
  va_list copy;
  va_copy(copy, ap);
  if (level <= LOG_ERROR) {
    /* simavr says why (an invalid opcode, a data address past RAM), then "avr_sadly_crashed":
     * the first is the report's; its colour codes and "CORE: *** " are not. */
    char said[sizeof last_error], plain[sizeof last_error];
    vsnprintf(said, sizeof said, format, copy);
    size_t n = 0;
    for (const char *c = said; *c && *c != '\n'; ++c) {
      if (*c == '\033') { /* a colour: ESC [ ... m */
        c += strcspn(c, "m");
        if (!*c) break;
        continue;
      }
      plain[n++] = *c;
    }
    plain[n] = 0;
    const char *text = strncmp(plain, "CORE: *** ", 10) == 0 ? plain + 10 : plain;
    if (*text && !(strcmp(text, "avr_sadly_crashed") == 0 && last_error[0]))
      snprintf(last_error, sizeof last_error, "%s", text);
  }
  va_end(copy);
  vfprintf(stderr, format, ap);
}

/* The CPU never sleeps on the host's clock: a sleeping chip's cycles jump to its next timer
 * (at the latest the slice's end), which the core does itself after this returns. */
static void no_sleep(avr_t *avr, avr_cycle_count_t how_long) {
  (void)avr;
  avr_profile_sleep(how_long + 1); /* what the core adds to its cycle count after this */
}

static avr_cycle_count_t slice_ends(avr_t *avr, avr_cycle_count_t when, void *param) {
  (void)avr;
  (void)when;
  (void)param;
  return 0;
}

static void set_slice_end(uint64_t cycle) {
  slice_end_cycle = cycle;
  avr_cycle_timer_cancel(engine.avr, slice_ends, NULL);
  const uint64_t now = engine.avr->cycle;
  avr_cycle_timer_register(engine.avr, cycle > now ? cycle - now : 1, slice_ends, NULL);
}

/* A device's next event falls within the running slice: end the slice there. */
void board_device_event_at(int64_t t_ns) {
  const uint64_t c = engine_cycle_at_or_after(t_ns);
  if (c < slice_end_cycle) set_slice_end(c > engine.avr->cycle ? c : engine.avr->cycle + 1);
}

/* The stack pointer from its two registers, each read as a byte: simavr stores them a byte at a
 * time, and one 16-bit load of two bytes just stored waits for both stores to retire (a
 * store-forwarding stall, the loop's costliest load in perf). */
static inline uint16_t stack_pointer_of(const uint8_t *data) {
  const volatile uint8_t *const bytes = data;
  return (uint16_t)(bytes[R_SPL] | bytes[R_SPH] << 8);
}

/* What the chip did when simavr stopped it, in the chip's terms. simavr stops the core on a
 * jump past the program, on a jump to the reset vector (a watchdog reset comes this way too),
 * and on a stack pointer past RAMEND. */
static void check_state(int state) {
  avr_t *avr = engine.avr;
  const unsigned pc = (unsigned)avr->pc;
  const uint64_t cycle = avr->cycle;
  if (state == cpu_Done)
    engine_fatal("the ATmega2560 halted: sleep with interrupts off (cli; sleep) at pc 0x%05x, cycle %" PRIu64, pc, cycle);
  if (pc >= avr->codeend)
    engine_fatal("the ATmega2560 jumped into nowhere: pc 0x%05x is past the program's end at 0x%05x (cycle %" PRIu64 ")",
                 pc, (unsigned)avr->codeend, cycle);
  const uint16_t sp = stack_pointer_of(avr->data);
  if (sp > avr->ramend)
    engine_fatal("the ATmega2560's stack pointer 0x%04x is past RAMEND 0x%04x (cycle %" PRIu64 ")", sp,
                 (unsigned)avr->ramend, cycle);
  if (pc == 0)
    engine_fatal("the ATmega2560 reset itself (a jump to the reset vector, or its watchdog) at cycle %" PRIu64, cycle);
  engine_fatal("the ATmega2560 crashed at pc 0x%05x, cycle %" PRIu64 ": %s", pc, cycle,
               last_error[0] ? last_error : "simavr stopped the core");
}

/* Resets after start-up (the watchdog's, in simavr, come through the core's reset hook). A
 * firmware the watchdog resets again and again never gets anywhere: three are a reset loop. */
#define RESET_LOOP 3
static unsigned resets, resets_seen;
static void (*core_reset)(avr_t *avr);

static void on_reset(avr_t *avr) {
  if (core_reset) core_reset(avr);
  resets++;
}

static void check_resets(void) {
  resets_seen = resets;
  fprintf(stderr, "sear-avr-engine: the ATmega2560 reset at cycle %" PRIu64 "\n", (uint64_t)engine.avr->cycle);
  if (resets >= RESET_LOOP)
    engine_fatal("the ATmega2560 is in a reset loop: reset %u times, the last at cycle %" PRIu64 " (its watchdog?)",
                 resets, (uint64_t)engine.avr->cycle);
}

/* One instruction, or a local run of them (local_runs.h) of at most run_cycles cycles, as
 * simavr's own avr_callback_run_raw() runs one (avr_run() calls that through avr->run for each
 * instruction), with its two per-instruction calls made only when they have
 * work: the cycle timers when the first of them is due (simavr keeps them sorted, and our slice
 * end is always one of them), the interrupt controller when an interrupt is pending or was just
 * enabled (interrupt_state, which simavr's controller also returns on when 0). Those calls and
 * avr_run()'s cost more host time than the instructions did (perf on the avoider: 45% against
 * 30% in simavr's decoder); the avoider's outputs are the same bytes either way. */
static inline int step(avr_t *avr, avr_cycle_count_t run_cycles) {
  /* simavr puts its own callback in avr->run for what an instruction cannot do inside the core
   * (the watchdog's reset); that one runs as simavr would run it. */
  if (__builtin_expect(avr->run != avr_callback_run_raw, 0)) {
    avr->run(avr);
    if (resets != resets_seen) check_resets(); /* only such a callback resets the chip */
    return avr->state;
  }
  avr_flashaddr_t new_pc = avr->pc;
  if (avr->state == cpu_Running) {
    /* The core goes on to the next instruction while this is above the cycles it ran; 0 is
     * one instruction. A cycle timer (re)registered meanwhile sets it to 1 (simavr keeps
     * run_cycle_limit at 1), and a store to SREG or SP to 0: either ends it there. */
    avr->run_cycle_count = run_cycles;
    new_pc = avr_run_one(avr);
    /* Most instructions leave the chip running with no timer due and no interrupt pending. */
    const avr_cycle_timer_slot_p first = avr->cycle_timers.timer;
    if (__builtin_expect(avr->state == cpu_Running && !avr->interrupt_state && first && first->when > avr->cycle, 1)) {
      avr->pc = new_pc;
      return cpu_Running;
    }
  }
  const avr_cycle_timer_slot_p first = avr->cycle_timers.timer;
  avr_cycle_count_t sleep = 0;
  if (avr->state == cpu_Sleeping || (first && first->when <= avr->cycle)) sleep = avr_cycle_timer_process(avr);
  avr->pc = new_pc;
  if (avr->state == cpu_Sleeping) {
    if (!avr->sreg[S_I]) {
      avr->state = cpu_Done; /* as simavr: asleep with interrupts off never wakes */
      return avr->state;
    }
    avr->sleep(avr, sleep);
    avr->cycle += 1 + sleep;
  }
  if (avr->interrupt_state && (avr->state == cpu_Running || avr->state == cpu_Sleeping)) avr_service_interrupts(avr);
  return avr->state;
}

/* An instruction that ran and left the pc and the stack pointer where they were jumped to itself
 * (`rjmp .-2`, a branch to itself taken, `jmp` or `ijmp` to itself; a call would have pushed): it
 * changes nothing, so it runs for ever unless an interrupt preempts it, and after one it is there
 * again. The MCU halted when it began (`while (true);`, or avr-libc's exit(): `cli; rjmp .-2`): the
 * simulator is told once; the chip goes on, taking its interrupts while the I flag allows. */
static void note_halt(uint64_t cycle) {
  struct sear_link *link = engine.link;
  if (link->halt) return;
  int64_t t = engine_ns_of_cycle(cycle);
  if (t < engine.turn_start_ns) t = engine.turn_start_ns;
  if (t > engine.quantum_end_ns) t = engine.quantum_end_ns;
  link->halted_ns = t;
  link->halt = engine.avr->sreg[S_I] ? SEAR_HALT_EMPTY_LOOP : SEAR_HALT_EMPTY_LOOP_IRQ_OFF;
}

/* Runs per instruction or local run: what it checks beyond step() is kept in registers where
 * nothing else changes it (the data space is allocated once; only this loop moves the lowest
 * stack pointer and the I flag it last saw), and the stack pointer is read once (the one after
 * an instruction is the one before the next). A local run takes the stack to a new low or changes
 * the I flag only in its last instruction (the hooks of local_runs.c and its budgets end it
 * there), never jumps to itself, and leaves the function it began in (or the image) only by its
 * last instruction, so the checks after it see what they would have seen after each of its
 * instructions, and its cycles all go to that function in the profile (counted at its first
 * word). */
static void run_to(uint64_t cycle) {
  avr_t *avr = engine.avr;
  set_slice_end(cycle);
  const uint8_t *const data = avr->data;
  const uint32_t code_end = engine.code_end;
  uint16_t lowest_sp = engine.lowest_sp;
  uint16_t sp = stack_pointer_of(data);
  static uint8_t irq_seen; /* the I flag after the last instruction: reset clears it */
  uint8_t irq_on = irq_seen;
  while (avr->cycle < slice_end_cycle) {
    const uint32_t pc = avr->pc;
    const uint64_t before = avr->cycle;
    const uint16_t sp_before = sp;
    const int was = avr->state;
    uint64_t run_cycles = avr_run_budget[avr_profile_word(pc)];
    if (run_cycles) {
      /* The slice's end is a cycle timer, so the first timer bounds the run: it stops at the
       * instruction that reaches it, where one-by-one stepping would process it. */
      const avr_cycle_timer_slot_p first = avr->cycle_timers.timer;
      if (was == cpu_Running && !avr->interrupt_state && first && first->when > before && avr->run == avr_callback_run_raw) {
        if (run_cycles > first->when - before) run_cycles = first->when - before;
      } else {
        run_cycles = 0;
      }
    }
    const int state = step(avr, run_cycles);
    sp = stack_pointer_of(data);
    if (__builtin_expect(avr->pc == pc, 0) && !run_cycles && was == cpu_Running && state == cpu_Running && sp == sp_before)
      note_halt(before);
    avr_profile_count(pc, avr->cycle - before);
    if (__builtin_expect(avr->sreg[S_I] != irq_on, 0)) {
      irq_on = avr->sreg[S_I];
      avr_profile_interrupts_flag(irq_on, avr->pc, avr->cycle);
    }
    /* Past the image is erased flash, which the chip would run through to a reset. */
    /* The chip's program counter wraps within its flash; simavr's does not (a backward jump from
     * the start reads as 0xffffffxx), so the report gives the address the chip would be at. */
    if (__builtin_expect(avr->pc >= code_end, 0))
      engine_fatal("the ATmega2560 jumped into nowhere: pc 0x%05x is past the program's end at 0x%05x (from %spc 0x%05x, "
                   "cycle %" PRIu64 ")",
                   (unsigned)(avr->pc & avr->flashend), code_end,
                   run_cycles ? "the last instruction of a run from " : "", pc, (uint64_t)avr->cycle);
    if (__builtin_expect(state != cpu_Running && state != cpu_Sleeping, 0)) check_state(state);
    /* The stack grows down towards .data and .bss: past their end it overwrites globals. */
    if (__builtin_expect(sp < lowest_sp, 0)) {
      lowest_sp = engine.lowest_sp = sp;
      if (sp < engine.bss_end)
        engine_fatal("the ATmega2560's stack ran into .bss: SP 0x%04x is below __bss_end 0x%04x (pc 0x%05x, cycle %" PRIu64
                     ")",
                     sp, engine.bss_end, (unsigned)avr->pc, (uint64_t)avr->cycle);
    }
  }
  irq_seen = irq_on;
}

static int64_t min64(int64_t a, int64_t b) { return a < b ? a : b; }

/* One quantum: everything due is applied at its cycle, the chip runs between. */
static void run_quantum(void) {
  struct sear_link *link = engine.link;
  uint32_t sample_next = 0;
  const uint32_t samples = link->sample_count < SEAR_LINK_MAX_SAMPLES ? link->sample_count : SEAR_LINK_MAX_SAMPLES;
  for (;;) {
    /* An instruction that ran past the quantum's end carries its cycles into the next quantum,
     * and so do the events due in them: the link's clock is the end. */
    const int64_t now = min64(engine_ns_of_cycle(engine.avr->cycle), engine.quantum_end_ns);
    while (sample_next < samples && link->samples[sample_next].time_ns <= now)
      mcu_devices_sample(&link->samples[sample_next++]);
    mcu_devices_run_due(now);
    avr_usarts_run_due(now);
    if (engine.avr->cycle >= engine.quantum_end_cycle) break;
    int64_t next = engine.quantum_end_ns;
    if (sample_next < samples) next = min64(next, link->samples[sample_next].time_ns);
    next = min64(next, mcu_devices_next_event());
    next = min64(next, avr_usarts_next_ns());
    uint64_t until = engine_cycle_at_or_after(next);
    if (until > engine.quantum_end_cycle) until = engine.quantum_end_cycle;
    if (until <= engine.avr->cycle) until = engine.avr->cycle + 1;
    if (until - engine.avr->cycle > SLICE_CYCLES) until = engine.avr->cycle + SLICE_CYCLES;
    run_to(until);
    avr_pins_poll_pwm();
  }
}

/* Debian's simavr 1.6 reads ADC channels 8..15 wrongly (fixed in 1.7): refused rather than
 * answered with the wrong channel's volts. */
static void refuse_high_adc_channels(void) {
  static const uint8_t adc_slot[SEAR_INPUT_KIND_END] = {[SEAR_INPUT_GP2D12] = 1, [SEAR_INPUT_MAXBOTIX] = 1};
  const struct sear_link *link = engine.link;
  for (uint32_t i = 0; i < link->input_count && i < SEAR_LINK_MAX_INPUTS; ++i) {
    const uint32_t kind = link->inputs[i].kind;
    if (kind < SEAR_INPUT_KIND_END && adc_slot[kind] && link->inputs[i].pins[0] >= 8 &&
        link->inputs[i].pins[0] < SEAR_LINK_ADC_CHANNELS)
      engine_fatal("ADC channel %u (A%u) on engine avr: simavr 1.6 reads channels 8..15 wrongly; wire the "
                   "sensor to A0..A7 or use the native engine",
                   link->inputs[i].pins[0], link->inputs[i].pins[0]);
  }
}

/* The ATmega2560's data space is 64 KiB: past its RAMEND (0x21FF) lies the external memory
 * interface, which without external RAM reads undefined values. simavr 1.6 allocates avr->data
 * for 0..RAMEND only (avr_init) and, on an access past it, logs "Invalid read/write address"
 * and calls avr_sadly_crashed but still reads or writes avr->data[addr] (sim_core.c), up to
 * 0xFFFF (data addresses are uint16_t): a stray pointer in the firmware then reads past the
 * allocation or corrupts the host's heap. With the whole space allocated (zeroed: the chip's
 * value there is undefined), the access stays in memory of ours and the crash report still names
 * the address. Safe here: avr->data is a plain malloc() block that simavr reaches only through
 * avr->data (no peripheral keeps a pointer into it; avr_reset() writes through avr->data) and
 * frees in avr_terminate(); nothing has run yet, and realloc keeps the registers avr_init()'s
 * reset set. */
static void grow_data_space(avr_t *avr) {
  const size_t whole = 0x10000u, allocated = (size_t)avr->ramend + 1;
  uint8_t *data = realloc(avr->data, whole);
  if (!data) engine_fatal("out of memory for the ATmega2560's 64 KiB data space");
  memset(data + allocated, 0, whole - allocated);
  avr->data = data;
}

static void load_chip(const char *elf_path, const char *report_path) {
  static elf_firmware_t firmware; /* its symbols stay in use for the report */
  memset(&firmware, 0, sizeof firmware);
  if (elf_read_firmware(elf_path, &firmware) != 0) engine_fatal("cannot read the AVR image %s", elf_path);
  avr_t *avr = avr_make_mcu_by_name("atmega2560");
  if (!avr) engine_fatal("libsimavr has no ATmega2560");
  avr_init(avr);
  grow_data_space(avr);
  avr_load_firmware(avr, &firmware);
  /* .data and .bss from the start of the ATmega2560's SRAM at 0x200 (datasheet figure 8-2). */
  engine.bss_end = (uint16_t)(0x200u + firmware.datasize + firmware.bsssize);
  engine.lowest_sp = (uint16_t)avr->ramend;
  engine.code_end = firmware.flashbase + firmware.flashsize;
  avr->frequency = (uint32_t)engine.clock_hz;
  avr->vcc = avr->avcc = (uint32_t)(engine.link->avcc_v * 1000.0 + 0.5);
  avr->aref = (uint32_t)(engine.link->aref_v * 1000.0 + 0.5);
  avr->sleep = no_sleep;
  avr->log = LOG_ERROR;
  /* simavr 1.6 polls level-triggered external interrupts every cycle even when they are
   * disabled (simavr #465); the chip only does so once INTn is enabled, which the extint module
   * still honours without strict triggering. */
  for (uint8_t n = 0; n < 8; ++n) avr_extint_set_strict_lvl_trig(avr, n, 0);
  if (avr_timer_modes_define(avr) != 6) engine_fatal("libsimavr's ATmega2560 does not have the chip's six timers");
  core_reset = avr->reset;
  avr->reset = on_reset;
  engine.avr = avr;
  avr_pin_change_init(); /* its vectors before the profile hooks every vector */
  avr_profile_init(report_path, &firmware);
  avr_local_runs_init(engine.code_end);
}

int main(int argc, char **argv) {
  const char *elf = NULL, *report = NULL;
  double clock_hz = 16e6;
  for (int i = 1; i < argc; ++i) {
    if (strcmp(argv[i], "--clock-hz") == 0 && i + 1 < argc) clock_hz = atof(argv[++i]);
    else if (strcmp(argv[i], "--report") == 0 && i + 1 < argc) report = argv[++i];
    else elf = argv[i];
  }
  setvbuf(stdout, NULL, _IONBF, 0);
  engine.link = sear_end_attach("sear-avr-engine",
                                "sear-avr-engine runs an AVR image inside the SEAR simulator: start it through a "
                                "project whose <mcu> says engine=\"avr\", with `sear run PROJECT`.",
                                "sear-avr-engine: this engine does not match the simulator's link; rebuild it");
  if (!elf) engine_fatal("sear-avr-engine: no AVR image named (usage: sear-avr-engine --clock-hz HZ FIRMWARE.elf)");
  if (!(clock_hz >= 1e5 && clock_hz <= 32e6)) engine_fatal("--clock-hz %g: the ATmega2560 runs at up to 16 MHz", clock_hz);
  engine.clock_hz = (uint64_t)clock_hz;
  avr_global_logger_set(logger);
  refuse_high_adc_channels();
  load_chip(elf, report);
  avr_eeprom_load();
  avr_pins_init();
  avr_usage_init();
  avr_usarts_init();
  avr_buses_init();
  sear_end_wait_for_turn(engine.link);
  /* The devices start within the first turn, as in the native engine, so that the levels they
   * drive at once reach the simulator with that turn's events, and on pins that exist. */
  mcu_devices_init(engine.link);
  uint64_t quanta = 0;
  for (;;) {
    struct sear_link *link = engine.link;
    engine.turn_start_ns = link->clock_ns;
    engine.quantum_end_ns = link->quantum_end_ns;
    engine.quantum_end_cycle = engine_cycle_at_or_after(link->quantum_end_ns);
    avr_usarts_take_quantum();
    run_quantum();
    mcu_readings_publish();
    avr_usage_note_interrupts();
    /* Every tenth quantum (10 ms at the default step): the report is read after the run, and the
     * engine is stopped without warning, so it is kept nearly current at little cost. */
    if (++quanta % 10 == 0) avr_profile_write();
    link->clock_ns = engine.quantum_end_ns;
    link->chip_cycles = engine.avr->cycle;
    link->chip_busy_cycles = avr_profile_busy_cycles();
    hand_over(SEAR_REQUEST_QUANTUM_DONE);
  }
}
