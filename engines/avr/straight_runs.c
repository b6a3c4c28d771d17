/* Which instructions may run in a straight run (see straight_runs.h), by their encodings in the
 * AVR instruction set manual, and the register hooks that end a run where one-by-one stepping
 * would have looked. */
#include "straight_runs.h"

#include <stdlib.h>

#include <sim_avr.h>
#include <sim_io.h>

#include "engine.h"

uint8_t avr_straight[AVR_PROFILE_WORDS];
struct straight_run avr_straight_runs[AVR_PROFILE_WORDS];

/* The words whose whole run is known, for avr_straight_settle. */
static uint32_t *run_words;
static uint32_t run_word_count, run_word_room;

/* Straight: goes on to the next instruction, at a cycle count its opcode fixes, and changes the
 * I flag only by a store to SREG (hooked). The rest (CPSE, SBIC/SBIS, SBRC/SBRS, branches, jumps,
 * calls, returns, BSET/BCLR with CLI and SEI, SLEEP, BREAK, WDR, SPM, DES, the XMEGA-only XCH and
 * LA*, reserved encodings) run on their own. */
static uint8_t classify(uint16_t op) {
  const uint8_t one = STRAIGHT_UNSEEN, two = STRAIGHT_UNSEEN | STRAIGHT_TWO_WORDS;
  switch (op >> 12) {
  case 0x0: /* NOP, MOVW, MULS, MULSU/FMUL*, CPC, SBC, ADD */
    return (op & 0xff00) != 0x0000 || op == 0x0000 ? one : 0;
  case 0x1: /* CPSE skips; CP, SUB, ADC */
    return (op & 0xfc00) == 0x1000 ? 0 : one;
  case 0x2: case 0x3: case 0x4: case 0x5: case 0x6: case 0x7: /* AND EOR OR MOV, CPI SBCI SUBI ORI ANDI */
  case 0x8: case 0xa: /* LDD, STD (LD and ST through Y and Z) */
  case 0xb: /* IN, OUT */
  case 0xe: /* LDI */
    return one;
  case 0x9:
    switch ((op >> 8) & 0xf) {
    case 0x0: case 0x1: /* LDS, LD Z+/-Z, LPM Z/Z+, ELPM Z/Z+, LD Y+/-Y, LD X/X+/-X, POP */
      switch (op & 0xf) {
      case 0x0: return two;
      case 0x1: case 0x2: case 0x4: case 0x5: case 0x6: case 0x7:
      case 0x9: case 0xa: case 0xc: case 0xd: case 0xe: case 0xf: return one;
      default: return 0;
      }
    case 0x2: case 0x3: /* STS, ST Z+/-Z, ST Y+/-Y, ST X/X+/-X, PUSH */
      switch (op & 0xf) {
      case 0x0: return two;
      case 0x1: case 0x2: case 0x9: case 0xa: case 0xc: case 0xd: case 0xe: case 0xf: return one;
      default: return 0;
      }
    case 0x4: case 0x5: /* COM NEG SWAP INC ASR LSR ROR DEC */
      switch (op & 0xf) {
      case 0x0: case 0x1: case 0x2: case 0x3: case 0x5: case 0x6: case 0x7: case 0xa: return one;
      default: return 0;
      }
    case 0x6: case 0x7: /* ADIW, SBIW */
    case 0x8: case 0xa: /* CBI, SBI */
    case 0xc: case 0xd: case 0xe: case 0xf: /* MUL */
      return one;
    default: /* SBIC, SBIS */
      return 0;
    }
  case 0xf: /* BLD, BST; branches and SBRC/SBRS are not */
    return (op & 0xfc08) == 0xf800 ? one : 0;
  default: /* RJMP, RCALL */
    return 0;
  }
}

/* A store to SREG ends the run after its instruction, and so does one that takes the stack
 * pointer below its lowest yet: the loop then sees the I flag and the stack's low mark at the
 * cycle they changed (a PUSH or POP that stays above the mark changes neither). simavr calls a
 * hook on these registers instead of storing (sim_core.c's _avr_set_r; SREG's bits it splits out
 * before). SPL and SPH are stored one at a time; whichever comes second sees the whole new
 * pointer, and a half-stored one read low only ends a run early. */
static void sreg_stored(struct avr_t *avr, avr_io_addr_t addr, uint8_t v, void *param) {
  (void)param;
  avr->data[addr] = v;
  avr->run_cycle_count = 0;
}

static void stack_pointer_stored(struct avr_t *avr, avr_io_addr_t addr, uint8_t v, void *param) {
  (void)param;
  avr->data[addr] = v;
  /* From v, not from the byte just stored (which a 16-bit load would wait for). */
  const uint16_t sp = (uint16_t)(addr == R_SPL ? v | avr->data[R_SPH] << 8 : avr->data[R_SPL] | v << 8);
  if (sp < engine.lowest_sp) avr->run_cycle_count = 0;
}

uint64_t avr_straight_walk(uint32_t pc, uint64_t room, uint32_t code_end, uint32_t *end) {
  uint64_t cycles = 0, cut_cycles = 0; /* cut: where the walk first reached `room` */
  uint32_t at = pc, cut_at = pc;
  while (at < code_end) {
    const uint8_t kind = avr_straight[avr_straight_word(at)];
    if (!(kind & STRAIGHT_CYCLES)) break;
    cycles += kind & STRAIGHT_CYCLES;
    at = avr_straight_next(at, kind);
    if (!cut_cycles && cycles >= room) {
      cut_cycles = cycles;
      cut_at = at;
    }
  }
  /* Whole once it ends at an instruction that runs on its own (not at one not yet seen). */
  struct straight_run *run = &avr_straight_runs[avr_straight_word(pc)];
  if (cycles && (at >= code_end || avr_straight[avr_straight_word(at)] == 0) && cycles <= UINT16_MAX &&
      at - pc <= UINT16_MAX && !run->cycles) {
    if (run_word_count == run_word_room) {
      const uint32_t grown = run_word_room ? 2 * run_word_room : 1024;
      uint32_t *words = realloc(run_words, grown * sizeof *words);
      if (!words) engine_fatal("out of memory for the engine's straight runs");
      run_words = words;
      run_word_room = grown;
    }
    run_words[run_word_count++] = avr_straight_word(pc);
    *run = (struct straight_run){(uint16_t)cycles, (uint16_t)(at - pc), 0};
  }
  if (cycles > room) { /* as far as the room goes */
    *end = cut_at;
    return cut_cycles;
  }
  *end = at;
  return cycles;
}

uint64_t avr_straight_count(uint32_t pc, uint32_t ran_to, uint32_t end, uint64_t times) {
  uint64_t counted = 0;
  for (uint32_t at = pc; at != ran_to && at < end;) {
    const uint8_t kind = avr_straight[avr_straight_word(at)];
    avr_profile_count(at, times * (kind & STRAIGHT_CYCLES));
    counted += kind & STRAIGHT_CYCLES;
    at = avr_straight_next(at, kind);
  }
  return counted;
}

void avr_straight_settle(void) {
  for (uint32_t i = 0; i < run_word_count; ++i) {
    struct straight_run *run = &avr_straight_runs[run_words[i]];
    if (!run->times) continue;
    const uint32_t from = run_words[i] * 2u;
    avr_straight_count(from, from + run->bytes, from + run->bytes, run->times);
    run->times = 0;
  }
}

int avr_straight_init(uint32_t code_end) {
  avr_t *avr = engine.avr;
  const char *single = getenv("SEAR_AVR_SINGLE_STEP");
  if (single && *single && *single != '0') return 0;
  static const avr_io_addr_t hooked[] = {R_SREG, R_SPL, R_SPH};
  for (unsigned i = 0; i < sizeof hooked / sizeof *hooked; ++i)
    if (avr->io[AVR_DATA_TO_IO(hooked[i])].w.c) return 0;
  if (code_end > avr->flashend + 1) code_end = avr->flashend + 1;
  for (uint32_t pc = 0; pc + 1 < code_end; pc += 2) {
    const uint16_t op = (uint16_t)(avr->flash[pc] | avr->flash[pc + 1] << 8);
    if (op == 0x95e8 || op == 0x95f8) { /* SPM, SPM Z+ */
      for (uint32_t w = 0; w < AVR_PROFILE_WORDS; ++w) avr_straight[w] = 0;
      return 0;
    }
    avr_straight[avr_straight_word(pc)] = classify(op);
  }
  avr_register_io_write(avr, R_SREG, sreg_stored, NULL);
  avr_register_io_write(avr, R_SPL, stack_pointer_stored, NULL);
  avr_register_io_write(avr, R_SPH, stack_pointer_stored, NULL);
  return 1;
}
